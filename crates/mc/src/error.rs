//! Typed errors of the `mc` crate. Every variant names the offending field and value so the
//! CLI can print a one-line message without guessing.

/// Everything that can go wrong while building inputs or reading/writing MCML files.
#[derive(Debug, thiserror::Error)]
pub enum McError {
    /// A numeric input is outside its physical range (negative coefficient, η ≤ 0, …).
    #[error("invalid {field} = {value}: {reason}")]
    InvalidValue {
        /// The field, e.g. `layer 2 mu_s` or `sigma_a[G]`.
        field: String,
        /// The offending value as given.
        value: String,
        /// What the value must satisfy.
        reason: &'static str,
    },

    /// A text input (`.mci`, material TOML, config TOML, shard file) could not be parsed.
    #[error("{}", parse_message(source_name, *line, message))]
    Parse {
        /// File name (or other label) of the input.
        source_name: String,
        /// 1-based line, 0 when unknown.
        line: usize,
        /// What is wrong there.
        message: String,
    },

    /// Shards to merge do not belong to the same run.
    #[error("cannot merge shards: {0}")]
    ShardMismatch(String),

    /// A file could not be read or written; `what` says which and what was being done
    /// (`cannot write out/x.csv`).
    #[error("{what}: {io}")]
    File {
        /// What was being done, naming the file.
        what: String,
        /// What the file system said.
        io: std::io::Error,
    },

    /// A shard slice (`I/N`, `auto`, `auto/N`) or the job array's environment it is read from is
    /// refused; the message names the value or variable.
    #[error("{0}")]
    Slice(String),

    /// An artist's material (`--from-artist KEY=VALUE …`) is refused; the message names the key.
    #[error("{0}")]
    Artist(String),

    /// Shard labels that are not one `MATERIAL:R`, `MATERIAL:G`, `MATERIAL:B` triple per
    /// material with a plain file name as `MATERIAL`.
    #[error(
        "invalid shard label {label:?}: expected MATERIAL:{channel} with MATERIAL a plain file name"
    )]
    ShardLabel {
        /// The offending label.
        label: String,
        /// The channel expected at its place.
        channel: &'static str,
    },

    /// Shards whose channel count is not three per material.
    #[error("invalid shard labels: {0} channels is not three per material")]
    ShardLabelCount(usize),
}

impl McError {
    pub(crate) fn invalid(
        field: impl Into<String>,
        value: impl ToString,
        reason: &'static str,
    ) -> Self {
        McError::InvalidValue {
            field: field.into(),
            value: value.to_string(),
            reason,
        }
    }

    /// A number as a user would write it: plain decimals, but exponent notation where the
    /// decimal expansion would run to hundreds of digits (1e308, 1e-320).
    pub(crate) fn number(v: f64) -> String {
        if v != 0.0 && v.is_finite() && !(1e-4..1e16).contains(&v.abs()) {
            format!("{v:e}")
        } else {
            v.to_string()
        }
    }

    /// A TOML error with the line it points at.
    pub(crate) fn toml(text: &str, source_name: &str, e: toml::de::Error) -> Self {
        // The line the span starts on: one more than the line breaks before it (a span at the
        // start of a line follows that line's break). A missing field has no line of its own.
        let line = match e.span() {
            Some(_) if e.message().starts_with("missing field") => 0,
            Some(s) => (text[..s.start].matches('\n').count() + 1).min(text.lines().count().max(1)),
            None => 0,
        };
        McError::parse(source_name, line, e.message().to_string())
    }

    /// A file error: `what` (naming the file), then the file system's message.
    pub fn file(what: impl Into<String>, io: std::io::Error) -> Self {
        McError::File {
            what: what.into(),
            io,
        }
    }

    pub(crate) fn parse(
        source_name: impl Into<String>,
        line: usize,
        message: impl Into<String>,
    ) -> Self {
        McError::Parse {
            source_name: source_name.into(),
            line,
            message: message.into(),
        }
    }
}

/// `file:line: message`, or `file: message` where the line is unknown (0).
fn parse_message(source_name: &str, line: usize, message: &str) -> String {
    match line {
        0 => format!("{source_name}: {message}"),
        l => format!("{source_name}:{l}: {message}"),
    }
}

/// Result with [`McError`].
pub type Result<T> = std::result::Result<T, McError>;
