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
    /// The most device memory a solver may take, where it is limited
    /// (`SPHCONTACT_GPU_MEMORY`, bytes).
    pub memory_budget: Option<u64>,
    /// The first error the device reported outside an error scope, or its
    /// loss: the run stops on it (exit status 1) instead of reading back
    /// what the device no longer computes.
    fault: Arc<Mutex<Option<String>>>,
    modules: Mutex<HashMap<String, Arc<(wgpu::ShaderModule, shaders::Reflected)>>>,
    pipelines: Mutex<HashMap<PipelineKey, Arc<Pipeline>>>,
}

/// The environment's limit on what the solver requests, in bytes: `None`
/// where unset, an error naming the variable where it is not a positive
/// whole number.
fn byte_limit(var: &str) -> Result<Option<u64>, String> {
    super::env_value(var, |&b: &u64| b > 0, "a whole number of bytes > 0")
}

/// The limits the solver requests: the adapter's, with the largest buffer
/// and storage binding lowered to `SPHCONTACT_GPU_MAX_BUFFER` bytes where
/// it is set (a smaller device's limits on any device: tests, or a device
/// shared with other work).
fn requested_limits(adapter: &wgpu::Limits) -> Result<wgpu::Limits, String> {
    let mut limits = adapter.clone();
    if let Some(b) = byte_limit("SPHCONTACT_GPU_MAX_BUFFER")? {
        limits.max_buffer_size = limits.max_buffer_size.min(b);
        limits.max_storage_buffer_binding_size = limits.max_storage_buffer_binding_size.min(b);
    }
    Ok(limits)
}

/// Keep the first fault the device reports.
fn record(fault: &Mutex<Option<String>>, what: String) {
    let mut f = fault.lock().unwrap_or_else(|e| e.into_inner());
    f.get_or_insert(what);
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
        // Where the driver reports a memory budget (Vulkan's
        // VK_EXT_memory_budget), a buffer past it is an out-of-memory
        // error the solver's build reports, not an overcommitted device.
        desc.memory_budget_thresholds = wgpu::MemoryBudgetThresholds {
            for_resource_creation: Some(95),
            for_device_loss: None,
        };
        let instance = wgpu::Instance::new(desc);
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            apply_limit_buckets: false,
        }))
        .map_err(|e| format!("no GPU adapter: {e}"))?;
        let info = adapter.get_info();
        let limits = requested_limits(&adapter.limits())?;
        let memory_budget = byte_limit("SPHCONTACT_GPU_MEMORY")?;
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
        // A fault is kept for the run to report, not raised as a panic
        // inside the device's callbacks.
        let fault = Arc::new(Mutex::new(None));
        let f = fault.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            record(&f, format!("the device reported an error: {e}"))
        }));
        let f = fault.clone();
        device.set_device_lost_callback(move |reason, message| {
            let why = if message.is_empty() {
                String::new()
            } else {
                format!(": {message}")
            };
            record(&f, format!("the device was lost ({reason:?}){why}"))
        });
        Ok(Self {
            device,
            queue,
            info,
            limits,
            memory_budget,
            fault,
            timestamps,
            modules: Mutex::new(HashMap::new()),
            pipelines: Mutex::new(HashMap::new()),
        })
    }

    /// The device's first fault (an error outside an error scope, or its
    /// loss), if it has had one.
    pub fn fault(&self) -> Option<String> {
        self.fault.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }

    /// Keep `what` as the device's fault unless it already has one (a
    /// readback that failed).
    pub(super) fn record_fault(&self, what: String) {
        record(&self.fault, what);
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
