//! Ctrl-C is not a death: SIGINT and SIGTERM of `fixplan run` and
//! `fixplan coordinator` stop the run in order, so that the parts in
//! flight are not suspects at the next `--resume` (an uncaught signal
//! reads as a death in the journal, and Ctrl-C twice on the same slow part
//! would fail it).
//!
//! Why last words and an exit rather than unwinding: a part being solved
//! cannot be stopped midway, so waiting for the parts in flight could take
//! hours. The process ends at once, as a kill would, but first the run
//! says what it must ([`LastWords`]): the journal gets `end interrupted`,
//! the results file is not cut inside a chunk (the words wait for the
//! chunk being written and no other starts), local workers are stopped.
//! The exit status is 128 + the signal (130, 143), as a shell reports a
//! process the signal ended. A second signal ends the process at once,
//! even if the last words are stuck (a disk that does not answer).
//!
//! The handler itself only does what is safe in a signal handler (an
//! atomic, `write(2)`, `_exit(2)`): it wakes a thread through a pipe, and
//! that thread says the last words. (Done with `libc`, already a
//! dependency: the signal crates would change the features of crates
//! below zenoh and rebuild them all.)

use anyhow::{bail, Result};
use libc::{c_int, SIGINT, SIGTERM};
use std::io::Read;
use std::os::fd::FromRawFd;
use std::sync::atomic::{AtomicBool, AtomicI32, AtomicU64, Ordering};
use std::sync::{Mutex, OnceLock};

/// What a run says before the process ends on a signal.
type Words = Box<dyn Fn() + Send>;

/// The words of the runs of this process, each under its key.
static SPEAKERS: Mutex<Vec<(u64, Words)>> = Mutex::new(Vec::new());
/// The key of the next [`LastWords`].
static NEXT_KEY: AtomicU64 = AtomicU64::new(0);
/// Set by the first signal: no more work is handed out.
static STOPPING: AtomicBool = AtomicBool::new(false);
/// The write end of the pipe that wakes the signal thread.
static WAKE: AtomicI32 = AtomicI32::new(-1);

/// Whether the process is stopping on a signal.
pub fn stopping() -> bool {
    STOPPING.load(Ordering::SeqCst)
}

/// Words said, in the order given, when a signal ends the process while
/// this value lives; forgotten when it is dropped (the run is over).
pub struct LastWords(u64);

impl LastWords {
    /// Registers `words`.
    pub fn say(words: impl Fn() + Send + 'static) -> LastWords {
        let key = NEXT_KEY.fetch_add(1, Ordering::SeqCst);
        lock_speakers().push((key, Box::new(words)));
        LastWords(key)
    }
}

impl Drop for LastWords {
    fn drop(&mut self) {
        lock_speakers().retain(|(k, _)| *k != self.0);
    }
}

/// Removes `path` if a signal ends the process: a unix socket this
/// process listens on, which zenoh removes only when its session closes.
/// Its name is unique to the process, so the words stay said until the
/// process ends.
pub fn remove_on_signal(path: std::path::PathBuf) {
    std::mem::forget(LastWords::say(move || {
        let _ = std::fs::remove_file(&path);
    }));
}

fn lock_speakers() -> std::sync::MutexGuard<'static, Vec<(u64, Words)>> {
    SPEAKERS.lock().unwrap_or_else(|e| e.into_inner())
}

/// The handler: the first signal wakes the signal thread with its
/// number, a second one ends the process at once.
extern "C" fn on_signal(signal: c_int) {
    if STOPPING.swap(true, Ordering::SeqCst) {
        // SAFETY: _exit is async-signal-safe.
        unsafe { libc::_exit(128 + signal) };
    }
    let byte = signal as u8;
    // SAFETY: write is async-signal-safe; a closed or full pipe only
    // loses the wake-up (the second signal still ends the process).
    unsafe {
        libc::write(
            WAKE.load(Ordering::SeqCst),
            std::ptr::from_ref(&byte).cast(),
            1,
        )
    };
}

/// Catches SIGINT and SIGTERM for the rest of the process (once; later
/// calls do nothing). Worker processes started after it get the default
/// handling back when they exec.
pub fn catch() -> Result<()> {
    static CAUGHT: OnceLock<()> = OnceLock::new();
    if CAUGHT.get().is_some() {
        return Ok(());
    }
    let mut fds = [-1 as c_int; 2];
    // SAFETY: pipe2 writes two descriptors into the array it is given.
    if unsafe { libc::pipe2(fds.as_mut_ptr(), libc::O_CLOEXEC) } != 0 {
        bail!(
            "cannot catch SIGINT/SIGTERM: {}",
            std::io::Error::last_os_error()
        );
    }
    // SAFETY: fds[0] is the pipe's read end, owned by nothing else.
    let mut wake = unsafe { std::fs::File::from_raw_fd(fds[0]) };
    WAKE.store(fds[1], Ordering::SeqCst);
    std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            let mut byte = [0u8; 1];
            if wake.read_exact(&mut byte).is_ok() {
                stop(c_int::from(byte[0]));
            }
        })?;
    for signal in [SIGINT, SIGTERM] {
        // SAFETY: a zeroed sigaction is a valid empty one; the handler
        // only does async-signal-safe things.
        let failed = unsafe {
            let mut action: libc::sigaction = std::mem::zeroed();
            action.sa_sigaction = on_signal as extern "C" fn(c_int) as libc::sighandler_t;
            action.sa_flags = libc::SA_RESTART;
            libc::sigemptyset(&mut action.sa_mask);
            libc::sigaction(signal, &action, std::ptr::null_mut()) != 0
        };
        if failed {
            bail!(
                "cannot catch SIGINT/SIGTERM: {}",
                std::io::Error::last_os_error()
            );
        }
    }
    let _ = CAUGHT.set(());
    Ok(())
}

/// The first signal: no more work, the last words, the exit.
fn stop(signal: c_int) -> ! {
    let name = if signal == SIGINT {
        "SIGINT"
    } else {
        "SIGTERM"
    };
    eprintln!("fixplan: {name}: stopping (a second one ends the process at once)");
    for (_, words) in lock_speakers().iter() {
        words();
    }
    std::process::exit(128 + signal)
}
