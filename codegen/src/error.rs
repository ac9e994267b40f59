//! Errors of the generator: every one names the problem and where it is.

pub use ffr_spec::Location;

/// Everything that can go wrong between a shape description and generated code.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum Error {
    /// A scene file that does not parse or does not make sense.
    #[error("{location}: {message}")]
    Scene {
        /// Where.
        location: Location,
        /// What was found and what is allowed.
        message: String,
    },
    /// A shape file that does not parse or does not make sense.
    #[error("{location}: {message}")]
    Shape {
        /// Where.
        location: Location,
        /// What was found and what was expected.
        message: String,
    },
    /// A shape name that is neither built in nor a path.
    #[error("unknown shape `{name}`: expected one of {known}, or a path to a .toml shape file")]
    UnknownShape {
        /// The name given.
        name: String,
        /// The built-in names.
        known: String,
    },
    /// A file that cannot be read or written.
    #[error("{}: {message}", ffr_spec::text::path_text(path))]
    Io {
        /// The file.
        path: String,
        /// The operating system's message.
        message: String,
    },
    /// A body description that is not valid (element count, reference condition, …).
    #[error("invalid body: {0}")]
    Body(String),
    /// A section integral the model has no constant for.
    #[error("shape `{shape}`: the term `{term}` needs a section moment the model does not have (only A, I_y, I_z)")]
    Section {
        /// Shape name.
        shape: String,
        /// The monomial.
        term: String,
    },
    /// A parameter value that is not valid (non-finite, or physically
    /// impossible: non-positive density, negative second moment, …).
    #[error("parameter `{name}` {message}")]
    Parameter {
        /// The parameter's field name (`rho`, `area`, …).
        name: String,
        /// What is wrong, with the value found.
        message: String,
    },
    /// A computed result that is not valid: a number that is not finite, a
    /// mass matrix diagonal that is not positive, a literal beyond `f64`.
    #[error("{quantity} {message}")]
    Invalid {
        /// The quantity, as `invariants --json` names it (`Kff[0][0]`).
        quantity: String,
        /// What is wrong.
        message: String,
    },
    /// A name that cannot be used in generated code (type or body name).
    #[error("{0}")]
    Name(String),
}
