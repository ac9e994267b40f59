//! The library's error: one type a user can match on, with the messages of
//! the part that failed (the generator, the runtime, a scene file, a file).

/// Everything the `ffr` library can refuse or fail at.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The generator refused a shape, body or parameter set.
    #[cfg(feature = "scene-files")]
    #[error(transparent)]
    Codegen(#[from] crate::codegen::Error),
    /// A modal reduction failed (an eigenproblem, a basis, an energy).
    #[cfg(feature = "scene-files")]
    #[error(transparent)]
    Modal(#[from] crate::codegen::modal::ModalError),
    /// The runtime refused a body or system, or a run failed (no
    /// convergence, divergence, a singular matrix).
    #[error(transparent)]
    Runtime(#[from] crate::runtime::Error),
    /// A scene does not load: where and what.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A file could not be read or written.
    #[error(transparent)]
    Io(#[from] std::io::Error),
    /// A body or reduction the library refuses; the message says why and
    /// what is allowed.
    #[error("{0}")]
    Invalid(String),
}

impl From<String> for Error {
    fn from(message: String) -> Self {
        Error::Invalid(message)
    }
}

impl From<&str> for Error {
    fn from(message: &str) -> Self {
        Error::Invalid(message.to_string())
    }
}

/// A scene that does not load: where and what.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// `file:line:col`, when the problem has a place.
    pub location: Option<crate::runtime::spec::Location>,
    /// What is wrong and what is allowed.
    pub message: String,
}

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.location {
            Some(l) => write!(f, "{l}: {}", self.message),
            None => f.write_str(&self.message),
        }
    }
}

impl std::error::Error for SceneError {}

/// `Result` with the library's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
