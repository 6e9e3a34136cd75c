//! The device: adapter selection, limits, and a cache of compiled
//! pipelines keyed by stage, entry point and override constants.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use super::shaders::{self, BindingUse};

/// A compiled entry point with the bindings it uses.
pub struct Pipeline {
    pub pipeline: wgpu::ComputePipeline,
    pub layout: wgpu::BindGroupLayout,
    pub bindings: Vec<BindingUse>,
}

type PipelineKey = (String, String, Vec<(String, u64)>);

/// An adapter, its device and queue.
pub struct GpuContext {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    pub limits: wgpu::Limits,
    /// Timestamp queries between dispatches inside a compute pass (for
    /// profiling real steps): requested where the adapter has them, which
    /// costs nothing until a query is written.
    pub timestamps: bool,
    modules: Mutex<HashMap<String, Arc<(wgpu::ShaderModule, shaders::Reflected)>>>,
    pipelines: Mutex<HashMap<PipelineKey, Arc<Pipeline>>>,
}

impl GpuContext {
    /// Open the best adapter (a discrete GPU first) with all its limits.
    /// `Err` says why there is none.
    pub fn new() -> Result<Self, String> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        // Compute needs no GL; leaving it out also keeps the GL loader from
        // probing for a display. WGPU_BACKEND still chooses explicitly.
        if std::env::var_os("WGPU_BACKEND").is_none() {
            desc.backends = wgpu::Backends::PRIMARY;
        }
        let instance = wgpu::Instance::new(desc);
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            apply_limit_buckets: false,
        }))
        .map_err(|e| format!("no GPU adapter: {e}"))?;
        let info = adapter.get_info();
        let limits = adapter.limits();
        let stamps = wgpu::Features::TIMESTAMP_QUERY
            | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS
            | wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES;
        let timestamps = adapter.features().contains(stamps);
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("sphcontact"),
            required_features: if timestamps {
                stamps
            } else {
                wgpu::Features::empty()
            },
            required_limits: limits.clone(),
            experimental_features: Default::default(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: Default::default(),
        }))
        .map_err(|e| format!("GPU adapter {}: no device: {e}", info.name))?;
        Ok(Self {
            device,
            queue,
            info,
            limits,
            timestamps,
            modules: Mutex::new(HashMap::new()),
            pipelines: Mutex::new(HashMap::new()),
        })
    }

    /// A software rasteriser (lavapipe, llvmpipe, WARP) rather than a GPU.
    pub fn is_software(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }

    /// "name (backend, device type)", as `summary.json` records it.
    pub fn adapter_name(&self) -> String {
        format!(
            "{} ({:?}, {:?})",
            self.info.name, self.info.backend, self.info.device_type
        )
    }

    fn module(&self, stage: &str, prelude: &str) -> Arc<(wgpu::ShaderModule, shaders::Reflected)> {
        let mut m = self.modules.lock().expect("module cache");
        m.entry(source_key(stage, prelude))
            .or_insert_with(|| {
                let refl = shaders::reflect(stage, prelude).unwrap_or_else(|e| panic!("{e}"));
                let src = shaders::source(stage, prelude);
                let desc = wgpu::ShaderModuleDescriptor {
                    label: Some(stage),
                    source: wgpu::ShaderSource::Wgsl(src.into()),
                };
                let module = self.device.create_shader_module(desc);
                Arc::new((module, refl))
            })
            .clone()
    }

    /// The pipeline of `stage::entry` with the generated constants
    /// `prelude` ([`shaders::source`]) and these override constants,
    /// compiled once per context.
    pub fn pipeline(
        &self,
        stage: &str,
        prelude: &str,
        entry: &str,
        constants: &[(&str, f64)],
    ) -> Arc<Pipeline> {
        let key: PipelineKey = (
            source_key(stage, prelude),
            entry.to_string(),
            constants
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_bits()))
                .collect(),
        );
        if let Some(p) = self.pipelines.lock().expect("pipeline cache").get(&key) {
            return p.clone();
        }
        let module = self.module(stage, prelude);
        let bindings = module.1.bindings(entry);
        let entries: Vec<wgpu::BindGroupLayoutEntry> = bindings
            .iter()
            .map(|b| wgpu::BindGroupLayoutEntry {
                binding: b.binding,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: if b.uniform {
                        wgpu::BufferBindingType::Uniform
                    } else {
                        wgpu::BufferBindingType::Storage {
                            read_only: b.read_only,
                        }
                    },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            })
            .collect();
        let label = format!("{stage}::{entry}");
        let layout = self
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(&label),
                entries: &entries,
            });
        let pl = self
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(&label),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
        let pipeline = self
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(&label),
                layout: Some(&pl),
                module: &module.0,
                entry_point: Some(entry),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants,
                    zero_initialize_workgroup_memory: false,
                },
                cache: None,
            });
        let p = Arc::new(Pipeline {
            pipeline,
            layout,
            bindings,
        });
        self.pipelines
            .lock()
            .expect("pipeline cache")
            .insert(key, p.clone());
        p
    }
}

/// What a stage's compiled module is cached under: the stage and the
/// scene's generated prelude ([`shaders::source`]).
fn source_key(stage: &str, prelude: &str) -> String {
    format!("{stage}\n{prelude}")
}
