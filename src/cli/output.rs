//! Standard output for data and summaries. A reader that closes the pipe early (`scm diff DIR | head -1`)
//! is a normal end in a shell pipeline: the process exits 0 without a word, as ripgrep does, instead of
//! panicking the way `println!` does.

use std::io::Write;

/// Writes `args` to stdout. A closed pipe ends the process with exit 0; any other write error ends it
/// with one line on stderr and exit 1.
pub fn emit(args: std::fmt::Arguments) {
    let mut stdout = std::io::stdout().lock();
    if let Err(e) = stdout.write_fmt(args).and_then(|()| stdout.flush()) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        // stderr may be closed too; nothing more can be said then.
        let _ = writeln!(std::io::stderr(), "scm: error: standard output: {e}");
        std::process::exit(1);
    }
}

/// `print!` through [`emit`].
macro_rules! out {
    ($($arg:tt)*) => { $crate::cli::output::emit(format_args!($($arg)*)) };
}

/// `println!` through [`emit`].
macro_rules! outln {
    ($($arg:tt)*) => { $crate::cli::output::emit(format_args!("{}\n", format_args!($($arg)*))) };
}

pub(crate) use {out, outln};
