//! `sphcontact doctor`: which graphics back ends, loaders and adapters the
//! solver can see, the limits it needs of them, whether `run` would take
//! the GPU path, and what to install where it would not (docs/usage.md,
//! "When the GPU is not found").

use std::path::{Path, PathBuf};

/// What the doctor found: its report, line by line, and whether a
/// hardware adapter is usable (the exit status: 0 if so, 1 if not).
pub struct Diagnosis {
    pub lines: Vec<String>,
    pub hardware: bool,
}

/// The directories the Vulkan loader reads driver manifests (ICD files)
/// from on Linux, in its order, before `XDG_DATA_DIRS`.
const ICD_DIRS: [&str; 4] = [
    "/etc/vulkan/icd.d",
    "/usr/local/etc/vulkan/icd.d",
    "/usr/local/share/vulkan/icd.d",
    "/usr/share/vulkan/icd.d",
];

/// Where the loader library usually lives.
const LIB_DIRS: [&str; 6] = [
    "/usr/lib/x86_64-linux-gnu",
    "/usr/lib/aarch64-linux-gnu",
    "/usr/lib64",
    "/usr/lib",
    "/lib/x86_64-linux-gnu",
    "/usr/local/lib",
];

/// The Vulkan loader library, where it is found (Linux; elsewhere the
/// platform ships its own).
fn vulkan_loader() -> Option<PathBuf> {
    let from_env = std::env::var("LD_LIBRARY_PATH").unwrap_or_default();
    let found = from_env
        .split(':')
        .filter(|d| !d.is_empty())
        .chain(LIB_DIRS)
        .map(|d| Path::new(d).join("libvulkan.so.1"))
        .find(|p| p.exists());
    found
}

/// The driver manifests the loader would read: those the environment
/// names (`VK_DRIVER_FILES`, or the older `VK_ICD_FILENAMES`), else every
/// `.json` of the standard directories and `XDG_DATA_DIRS`.
fn icd_files() -> (Vec<PathBuf>, Option<&'static str>) {
    for var in ["VK_DRIVER_FILES", "VK_ICD_FILENAMES"] {
        if let Ok(v) = std::env::var(var) {
            let files = v.split(':').filter(|f| !f.is_empty()).map(PathBuf::from);
            return (files.collect(), Some(var));
        }
    }
    let xdg = std::env::var("XDG_DATA_DIRS").unwrap_or_default();
    let dirs = ICD_DIRS.iter().map(PathBuf::from).chain(
        xdg.split(':')
            .filter(|d| !d.is_empty())
            .map(|d| Path::new(d).join("vulkan/icd.d")),
    );
    let mut files: Vec<PathBuf> = dirs
        .filter_map(|d| std::fs::read_dir(d).ok())
        .flatten()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    files.dedup();
    (files, None)
}

/// What a driver manifest is, by its file name.
fn icd_kind(file: &Path) -> &'static str {
    let name = file
        .file_name()
        .map(|n| n.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    if name.contains("lvp") {
        "lavapipe, Mesa's software rasteriser"
    } else if name.contains("nvidia") {
        "NVIDIA"
    } else if name.contains("radeon") || name.contains("amd") {
        "AMD"
    } else if name.contains("intel") {
        "Intel"
    } else {
        "other"
    }
}

/// How many storage buffers the solver's busiest entry point binds: the
/// adapter's `max_storage_buffers_per_shader_stage` must reach it.
pub fn storage_buffers_needed() -> u32 {
    let mut most = 0;
    for stage in crate::gpu::shaders::modules() {
        let prelude = crate::gpu::shaders::sample_prelude(stage);
        let Ok(r) = crate::gpu::shaders::reflect(stage, &prelude) else {
            continue;
        };
        for entry in r.entry_points() {
            let n = r.bindings(&entry).iter().filter(|b| !b.uniform).count();
            most = most.max(n as u32);
        }
    }
    most
}

/// One adapter's line and its limits against what the solver needs.
fn adapter_lines(a: &wgpu::Adapter, needed: u32, out: &mut Vec<String>) {
    let (info, l) = (a.get_info(), a.limits());
    let driver = [info.driver.as_str(), info.driver_info.as_str()]
        .iter()
        .filter(|s| !s.is_empty())
        .copied()
        .collect::<Vec<_>>()
        .join(" ");
    out.push(format!(
        "  {} ({:?}, {:?}{})",
        info.name,
        info.device_type,
        info.backend,
        if driver.is_empty() {
            String::new()
        } else {
            format!(", driver {driver}")
        }
    ));
    let mib = |b: u64| b as f64 / (1u64 << 20) as f64;
    let storage = l.max_storage_buffers_per_shader_stage;
    out.push(format!(
        "    storage buffers per stage {storage} (the solver needs {needed}{}), largest buffer {:.0} MiB, storage binding {:.0} MiB, workgroup storage {} B, invocations per workgroup {}",
        if storage < needed { ": TOO FEW" } else { "" },
        mib(l.max_buffer_size),
        mib(l.max_storage_buffer_binding_size),
        l.max_compute_workgroup_storage_size,
        l.max_compute_invocations_per_workgroup,
    ));
}

/// What to install when there is no usable hardware adapter.
fn advice(loader: bool, icds: &[PathBuf], out: &mut Vec<String>) {
    let nvidia_device = Path::new("/dev/nvidiactl").exists();
    let dri = Path::new("/dev/dri").exists();
    let hardware_icd = icds
        .iter()
        .any(|f| f.exists() && !icd_kind(f).starts_with("lavapipe"));
    out.push("to use a GPU:".into());
    if icds.iter().any(|f| !f.exists()) {
        out.push("  a driver manifest above is missing: correct VK_DRIVER_FILES (or VK_ICD_FILENAMES), or mount the file there".into());
    }
    if !loader {
        out.push("  install the Vulkan loader (Debian/Ubuntu: apt-get install libvulkan1)".into());
    }
    if nvidia_device && !icds.iter().any(|f| icd_kind(f) == "NVIDIA") {
        out.push("  an NVIDIA device is present (/dev/nvidiactl) but no NVIDIA driver manifest: install the driver's Vulkan part (Ubuntu: libnvidia-gl-<version>, matching the kernel driver), or in a container mount the host's nvidia_icd.json into /usr/share/vulkan/icd.d/ (or set VK_DRIVER_FILES to it) and start the container with NVIDIA_DRIVER_CAPABILITIES=compute,utility,graphics".into());
    } else if !hardware_icd {
        out.push("  install the GPU's Vulkan driver: Mesa for AMD and Intel (apt-get install mesa-vulkan-drivers), the vendor driver for NVIDIA; a container needs the device nodes (/dev/dri or /dev/nvidia*) and the driver manifest (an ICD .json in /usr/share/vulkan/icd.d/) from the host".into());
    }
    if !nvidia_device && !dri {
        out.push("  no GPU device node is visible here (/dev/dri, /dev/nvidia*): on a cluster, ask for a GPU node or pass the device into the container".into());
    }
}

/// Look at everything and say what was found.
pub fn diagnose() -> Diagnosis {
    let mut lines = Vec::new();
    let loader = vulkan_loader();
    if cfg!(target_os = "linux") {
        lines.push(match &loader {
            Some(p) => format!("Vulkan loader: {}", p.display()),
            None => "Vulkan loader: not found (libvulkan.so.1)".into(),
        });
        let (icds, var) = icd_files();
        lines.push(match var {
            Some(v) => format!("driver manifests ({v}):"),
            None => "driver manifests (ICD files):".into(),
        });
        if icds.is_empty() {
            lines.push("  none".into());
        }
        for f in &icds {
            let missing = if f.exists() { "" } else { " (missing)" };
            lines.push(format!("  {} ({}){missing}", f.display(), icd_kind(f)));
        }
        lines.push(String::new());
        let (hardware, run_lines) = adapters_and_choice();
        lines.extend(run_lines);
        if !hardware {
            advice(loader.is_some(), &icds, &mut lines);
        }
        return Diagnosis { lines, hardware };
    }
    let (hardware, run_lines) = adapters_and_choice();
    lines.extend(run_lines);
    Diagnosis { lines, hardware }
}

/// Every adapter of the back ends the solver opens, and the one `run`
/// would take.
fn adapters_and_choice() -> (bool, Vec<String>) {
    let mut out = Vec::new();
    let needed = storage_buffers_needed();
    // The back ends the solver opens (GpuContext::new): Vulkan, Metal and
    // DX12, unless WGPU_BACKEND names others.
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    if std::env::var_os("WGPU_BACKEND").is_none() {
        desc.backends = wgpu::Backends::PRIMARY;
    }
    let backends = desc.backends;
    let instance = wgpu::Instance::new(desc);
    let adapters = pollster::block_on(instance.enumerate_adapters(backends));
    let names: Vec<&str> = [
        (wgpu::Backends::VULKAN, "Vulkan"),
        (wgpu::Backends::METAL, "Metal"),
        (wgpu::Backends::DX12, "DX12"),
        (wgpu::Backends::GL, "GL"),
    ]
    .into_iter()
    .filter(|(b, _)| backends.contains(*b))
    .map(|(_, n)| n)
    .collect();
    out.push(format!(
        "adapters ({}; back ends {}):",
        adapters.len(),
        names.join(", ")
    ));
    if adapters.is_empty() {
        out.push("  none".into());
    }
    for a in &adapters {
        adapter_lines(a, needed, &mut out);
    }
    out.push(String::new());
    let hardware = match crate::gpu::GpuContext::new() {
        Ok(ctx) if !ctx.is_software() => {
            let allowed = ctx.limits.max_storage_buffers_per_shader_stage;
            if allowed >= needed {
                out.push(format!(
                    "run (backend auto) takes the GPU path: {}",
                    ctx.adapter_name()
                ));
            } else {
                out.push(format!(
                    "run (backend auto) would take {}, which allows {allowed} storage buffers per stage where the solver binds {needed}: its runs fail to build; use --backend cpu",
                    ctx.adapter_name()
                ));
            }
            allowed >= needed
        }
        Ok(ctx) => {
            out.push(format!(
                "run (backend auto) takes the CPU path: the only adapter is a software one ({}), slower than the CPU path on the same cores; --backend gpu uses it anyway",
                ctx.adapter_name()
            ));
            false
        }
        Err(e) => {
            out.push(format!("run (backend auto) takes the CPU path: {e}"));
            false
        }
    };
    (hardware, out)
}
