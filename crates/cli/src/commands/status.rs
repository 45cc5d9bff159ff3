//! How a command ended, and the exit status that tells the shell.

/// Exit status when every input line was answered.
const EXIT_OK: u8 = 0;
/// Exit status when some input lines could not be read as roads (the others were answered), a
/// run failed part-way, or (`--fail-on`) a failing road was found.
const EXIT_BAD_LINES: u8 = 1;
/// Exit status for bad usage (options, unreadable input file), and for `replay` and `suite` when
/// some input could not be used.
pub const EXIT_USAGE: u8 = 2;
/// Exit status after Ctrl-C or SIGTERM (128 + SIGINT), once the summary is written.
const EXIT_INTERRUPTED: u8 = 130;

/// How a command ended when it did not fail outright.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// Every input line was read and answered.
    AllRead,
    /// Some input lines were not roads; they were reported as `error` records.
    SomeLinesBad,
    /// The work failed part-way; what was computed was written, with the reason.
    Failed,
    /// Ctrl-C or SIGTERM ended the work early; what was computed was written.
    Interrupted,
    /// The work was done and found what the user asked to fail on (`--fail-on`): a failing road,
    /// or a road whose outcome changed.
    FailuresFound,
    /// Some input (a file, a line, a road) could not be used; the rest was done.
    BadInput,
}

impl Status {
    /// The process's exit status for this ending.
    pub fn exit_code(self) -> u8 {
        match self {
            Status::AllRead => EXIT_OK,
            Status::SomeLinesBad | Status::Failed | Status::FailuresFound => EXIT_BAD_LINES,
            Status::Interrupted => EXIT_INTERRUPTED,
            Status::BadInput => EXIT_USAGE,
        }
    }
}
