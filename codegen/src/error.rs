//! Errors of the generator: every one names the problem and where it is.

use std::fmt;

/// A place in a source text: `file:line:column` (1-based; columns count characters).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    /// File path or `built-in NAME`.
    pub file: String,
    /// Line, from 1.
    pub line: usize,
    /// Column, from 1.
    pub column: usize,
}

impl Location {
    /// The location of byte `offset` in `text`.
    pub fn of(file: &str, text: &str, offset: usize) -> Location {
        let mut offset = offset.min(text.len());
        while !text.is_char_boundary(offset) {
            offset -= 1;
        }
        let before = &text[..offset];
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let column = text[line_start..offset].chars().count() + 1;
        Location {
            file: file.to_string(),
            line,
            column,
        }
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file, self.line, self.column)
    }
}

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
    #[error("{path}: {message}")]
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
