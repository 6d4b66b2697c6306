//! What happens when the process must stop early: a panic in any thread, or
//! `SIGINT`, `SIGTERM`, `SIGHUP`. Either way the temporary files of writes in
//! progress are removed first and the whole process ends, so no worker thread
//! is left spinning and no half-written output stays behind.

use signal_hook::consts::signal::{SIGHUP, SIGINT, SIGTERM};
use signal_hook::iterator::Signals;

/// Installs the panic hook and the signal watcher. Call once, first thing in
/// `main`.
pub(crate) fn install() {
    std::panic::set_hook(Box::new(|info| {
        spatch_format::abandon_pending_writes();
        let payload = info.payload();
        let message = payload
            .downcast_ref::<&str>()
            .copied()
            .or_else(|| payload.downcast_ref::<String>().map(String::as_str))
            .unwrap_or("a panic without a message");
        let place = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()))
            .unwrap_or_default();
        let message = message.replace('\n', " ");
        eprintln!("spatch: error: internal error: {message}{place} (this is a bug in spatch)");
        // Ends every thread: a panicking worker must not leave the others
        // waiting for it.
        std::process::exit(1);
    }));
    // Without the watcher a signal still ends the process; only the clean-up
    // of temporary files is lost (the next run removes them).
    if let Ok(mut signals) = Signals::new([SIGINT, SIGTERM, SIGHUP]) {
        std::thread::spawn(move || {
            if let Some(signal) = signals.forever().next() {
                spatch_format::abandon_pending_writes();
                let _ = signal_hook::low_level::emulate_default_handler(signal);
                std::process::exit(128 + signal);
            }
        });
    }
}
