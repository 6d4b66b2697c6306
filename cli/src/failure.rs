//! Exit codes: what kind of failure an error is.

use std::process::ExitCode;

use spatch_render::RenderError;

/// How a run ended, when it did not succeed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Failure {
    /// Bad input or usage: exit code 2.
    BadInput,
    /// Spatch itself or the system failed (a bug, a full disk): exit code 1.
    Internal,
    /// The reader of our standard output went away: exit quietly with 0.
    BrokenPipe,
}

/// Marks an error as spatch's own fault or the system's (exit code 1)
/// rather than the input's.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub(crate) struct InternalFailure(pub(crate) String);

impl Failure {
    /// Looks through the error chain for what decides the exit code.
    pub(crate) fn classify(err: &anyhow::Error) -> Self {
        for cause in err.chain() {
            if let Some(io) = cause.downcast_ref::<std::io::Error>() {
                if io.kind() == std::io::ErrorKind::BrokenPipe {
                    return Self::BrokenPipe;
                }
            }
            if cause.downcast_ref::<InternalFailure>().is_some() {
                return Self::Internal;
            }
            if let Some(spatch_format::FormatError::Bug(_)) = cause.downcast_ref() {
                return Self::Internal;
            }
        }
        Self::BadInput
    }

    /// The process exit code.
    pub(crate) fn exit_code(self) -> ExitCode {
        match self {
            Self::BadInput => ExitCode::from(2),
            Self::Internal => ExitCode::from(1),
            Self::BrokenPipe => ExitCode::SUCCESS,
        }
    }
}

/// The error and its causes on one line, `outer: inner: …`, leaving out a
/// cause whose text the line already ends with (library errors that print
/// their source inside their own message would otherwise say it twice:
/// "invalid camera: X: X"). Line breaks inside a message become spaces.
pub(crate) fn one_line(err: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in err.chain() {
        let text = cause.to_string().replace(['\r', '\n'], " ");
        if line.ends_with(&text) {
            continue;
        }
        if !line.is_empty() {
            line.push_str(": ");
        }
        line.push_str(&text);
    }
    line
}

/// A render-library error as an exit-code-aware error.
pub(crate) fn render_failure(err: RenderError) -> anyhow::Error {
    match err {
        RenderError::Bug(_) | RenderError::ThreadPool { .. } | RenderError::Encode { .. } => {
            anyhow::Error::new(InternalFailure(err.to_string()))
        }
        other => anyhow::Error::new(other),
    }
}

#[cfg(test)]
mod tests {
    use super::one_line;

    #[derive(Debug, thiserror::Error)]
    #[error("inner problem")]
    struct Inner;

    #[derive(Debug, thiserror::Error)]
    #[error("outer: {0}")]
    struct Outer(#[source] Inner);

    #[test]
    fn a_cause_already_said_is_not_repeated() {
        let err = anyhow::Error::new(Outer(Inner)).context("a.spatch");
        assert_eq!(one_line(&err), "a.spatch: outer: inner problem");
        let err = anyhow::anyhow!("two\nlines").context("f");
        assert_eq!(one_line(&err), "f: two lines");
    }
}
