//! Typed errors. Bad input is a [`SceneError`] (exit status 2); a run that
//! fails after it started is a [`RunError`] (exit status 1).

use std::fmt;

/// Something wrong with a scene: the file, the key, and what is wrong.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneError {
    /// The scene's origin (usually its path).
    pub file: String,
    /// The offending key as a dotted path (`bodies[1].spacing`), with the
    /// line and column where TOML gives them.
    pub key: Option<String>,
    pub message: String,
}

impl SceneError {
    /// A validation error on `key` (the file is filled in later by `in_file`).
    pub fn at(key: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            file: String::new(),
            key: Some(key.into()),
            message: message.into(),
        }
    }

    pub fn in_file(mut self, origin: &str) -> Self {
        self.file = origin.to_string();
        self
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if !self.file.is_empty() {
            write!(f, "{}: ", self.file)?;
        }
        if let Some(k) = &self.key {
            write!(f, "{k}: ")?;
        }
        f.write_str(&self.message.replace('\n', " "))
    }
}

impl std::error::Error for SceneError {}

/// Where and why a run went unstable.
#[derive(Debug, Clone, PartialEq)]
pub struct Instability {
    pub step: u64,
    pub time: f64,
    pub body: String,
    /// Index of the particle within its body.
    pub particle: usize,
    pub quantity: String,
    pub value: f64,
}

impl fmt::Display for Instability {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "unstable at step {} (t = {:.6e} s): body '{}', particle {}: {} = {:e}",
            self.step, self.time, self.body, self.particle, self.quantity, self.value
        )
    }
}

/// A failure of the run itself (exit status 1), or of its set-up (exit 2):
/// what failed, and where ([`RunError::exit_code`] maps each to its
/// status).
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A command-line option that cannot be honoured: the option and why.
    #[error("{option} {message}")]
    Option {
        option: &'static str,
        message: String,
    },
    /// The backend asked for cannot run the scene: which (`gpu`, `cpu`)
    /// and why.
    #[error("backend {backend}: {message}")]
    Backend {
        backend: &'static str,
        message: String,
    },
    /// A checkpoint that cannot be written or resumed: its file and why.
    #[error("{path}: {message}")]
    Checkpoint { path: String, message: String },
    /// The run went unstable: where and why.
    #[error("{0}")]
    Unstable(Instability),
    /// The device failed during the run (lost, or an error it reported).
    #[error("{0}")]
    Device(String),
    #[error("{path}: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
    /// An output that could not be drawn: its file and why.
    #[error("{path}: {message}")]
    Plot { path: String, message: String },
}

impl RunError {
    /// The process exit status this error maps to (docs/scenes.md, "Exit
    /// status"): 2 for bad input (a scene, an option, a backend that cannot
    /// run the scene, a checkpoint that cannot be resumed), 1 for a run
    /// that failed.
    pub fn exit_code(&self) -> i32 {
        match self {
            RunError::Scene(_)
            | RunError::Option { .. }
            | RunError::Backend { .. }
            | RunError::Checkpoint { .. } => 2,
            RunError::Unstable(_)
            | RunError::Device(_)
            | RunError::Io { .. }
            | RunError::Plot { .. } => 1,
        }
    }

    /// A bad option.
    pub fn option(option: &'static str, message: impl Into<String>) -> Self {
        RunError::Option {
            option,
            message: message.into(),
        }
    }

    /// A checkpoint at `path` that cannot be used.
    pub fn checkpoint(path: impl Into<String>, message: impl Into<String>) -> Self {
        RunError::Checkpoint {
            path: path.into(),
            message: message.into(),
        }
    }

    pub fn io(path: impl AsRef<std::path::Path>, source: std::io::Error) -> Self {
        RunError::Io {
            path: path.as_ref().display().to_string(),
            source,
        }
    }
}
