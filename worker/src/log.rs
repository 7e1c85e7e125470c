//! The log line format of fixplan's processes, and the `tracing` subscriber
//! that the `fixplan` command installs once per process.
//!
//! Library code only emits `tracing` events, with a `role` field naming the
//! process (`coordinator`, `worker NAME`): a program or test that installs
//! no subscriber simply drops them. A line reads
//! `[   0.123s INFO coordinator] message`: seconds since the subscriber was
//! installed, the level, the role (the event's target when it has none, as
//! for zenoh's own warnings), the message and any other fields as
//! `key=value`, on one line of standard error.
//!
//! Without `RUST_LOG`, fixplan's crates log at `info` (`warn` with
//! `--quiet`) and every other crate at `error`: zenoh warns about settings
//! fixplan makes on purpose (gossip off) and about routine link retries. A
//! `RUST_LOG` filter (`RUST_LOG=info,zenoh=warn`) replaces that default
//! entirely.

use std::fmt::{self, Write as _};
use std::time::Instant;
use tracing::field::{Field, Visit};
use tracing::{Event, Subscriber};
use tracing_subscriber::filter::ParseError;
use tracing_subscriber::fmt::format::Writer;
use tracing_subscriber::fmt::{FmtContext, FormatEvent, FormatFields, MakeWriter};
use tracing_subscriber::layer::SubscriberExt;
use tracing_subscriber::registry::LookupSpan;
use tracing_subscriber::EnvFilter;

/// fixplan's crates: their events are the ones users asked for with the
/// default level; other crates (zenoh) are heard only on errors.
const OURS: [&str; 4] = [
    "fixplan_core",
    "fixplan_catalog",
    "fixplan_worker",
    "fixplan_coordinator",
];

/// The filter directives used when `RUST_LOG` is unset or empty.
pub fn default_directives(quiet: bool) -> String {
    let level = if quiet { "warn" } else { "info" };
    let mut d = String::from("error");
    for c in OURS {
        d.push_str(&format!(",{c}={level}"));
    }
    d
}

/// The filter of a process: `rust_log` when it is set and valid, else the
/// default. A `RUST_LOG` that cannot be parsed comes back as the error so
/// that it can be reported as a log line (through the writer that ignores
/// a closed standard error) instead of being dropped silently.
pub fn filter(quiet: bool, rust_log: Option<&str>) -> (EnvFilter, Option<ParseError>) {
    let default = || EnvFilter::new(default_directives(quiet));
    match rust_log.map(str::trim).filter(|s| !s.is_empty()) {
        None => (default(), None),
        Some(s) => match EnvFilter::try_new(s) {
            Ok(f) => (f, None),
            Err(e) => (default(), Some(e)),
        },
    }
}

/// One event as one line, with the time since the process's subscriber
/// was made (close to the process start: it is made first thing).
#[derive(Debug, Clone, Copy)]
pub struct LineFormat {
    start: Instant,
}

impl LineFormat {
    /// Times lines from now.
    pub fn new() -> LineFormat {
        LineFormat {
            start: Instant::now(),
        }
    }
}

impl Default for LineFormat {
    fn default() -> Self {
        Self::new()
    }
}

/// The fields of one event, sorted into the parts of the line.
#[derive(Default)]
struct Fields {
    message: String,
    role: Option<String>,
    rest: String,
}

impl Visit for Fields {
    fn record_str(&mut self, field: &Field, value: &str) {
        match field.name() {
            "message" => self.message.push_str(value),
            "role" => self.role = Some(value.to_string()),
            name => {
                let _ = write!(self.rest, " {name}={value:?}");
            }
        }
    }

    fn record_debug(&mut self, field: &Field, value: &dyn fmt::Debug) {
        match field.name() {
            "message" => {
                let _ = write!(self.message, "{value:?}");
            }
            "role" => self.role = Some(format!("{value:?}")),
            name => {
                let _ = write!(self.rest, " {name}={value:?}");
            }
        }
    }
}

/// Writes `s` with line breaks escaped: one event must stay one line for
/// whoever reads the log line by line.
fn write_one_line(w: &mut Writer<'_>, s: &str) -> fmt::Result {
    for (i, part) in s.split('\n').enumerate() {
        if i > 0 {
            w.write_str("\\n")?;
        }
        w.write_str(part.strip_suffix('\r').unwrap_or(part))?;
    }
    Ok(())
}

impl<S, N> FormatEvent<S, N> for LineFormat
where
    S: Subscriber + for<'a> LookupSpan<'a>,
    N: for<'a> FormatFields<'a> + 'static,
{
    fn format_event(
        &self,
        _ctx: &FmtContext<'_, S, N>,
        mut w: Writer<'_>,
        event: &Event<'_>,
    ) -> fmt::Result {
        let mut f = Fields::default();
        event.record(&mut f);
        let meta = event.metadata();
        let role = f.role.as_deref().unwrap_or(meta.target());
        let t = self.start.elapsed().as_secs_f64();
        write!(w, "[{t:9.3}s {} ", meta.level())?;
        write_one_line(&mut w, role)?;
        w.write_str("] ")?;
        write_one_line(&mut w, &f.message)?;
        write_one_line(&mut w, &f.rest)?;
        w.write_char('\n')
    }
}

/// The subscriber of a process: `filter` and [`LineFormat`] lines on
/// `writer`. Write errors are dropped, not reported: a closed standard
/// error (`fixplan run 2>&1 | head`) must neither panic nor stop a worker
/// or the coordinator in the middle of a run.
pub fn subscriber<W>(filter: EnvFilter, writer: W) -> impl Subscriber + Send + Sync
where
    W: for<'a> MakeWriter<'a> + Send + Sync + 'static,
{
    let lines = tracing_subscriber::fmt::layer()
        .event_format(LineFormat::new())
        .with_ansi(false)
        .with_writer(writer)
        .log_internal_errors(false);
    tracing_subscriber::registry().with(filter).with(lines)
}

/// Installs the process's subscriber: lines on standard error, filtered by
/// `RUST_LOG` or else by the default of `quiet` ([`default_directives`]).
/// For the command line's `main`; a second call changes nothing.
pub fn init(quiet: bool) {
    let rust_log = std::env::var("RUST_LOG").ok();
    let (filter, bad) = filter(quiet, rust_log.as_deref());
    let installed = tracing::subscriber::set_global_default(subscriber(filter, std::io::stderr));
    if let (Ok(()), Some(e)) = (installed, bad) {
        tracing::warn!(
            role = "fixplan",
            "RUST_LOG ignored ({e}); using the default filter"
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io;
    use std::sync::{Arc, Mutex};

    /// Collects what the subscriber writes.
    #[derive(Clone, Default)]
    struct Capture(Arc<Mutex<Vec<u8>>>);

    impl io::Write for Capture {
        fn write(&mut self, b: &[u8]) -> io::Result<usize> {
            self.0.lock().unwrap().extend_from_slice(b);
            Ok(b.len())
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    impl<'a> MakeWriter<'a> for Capture {
        type Writer = Capture;
        fn make_writer(&'a self) -> Capture {
            self.clone()
        }
    }

    impl Capture {
        fn text(&self) -> String {
            String::from_utf8(self.0.lock().unwrap().clone()).unwrap()
        }
    }

    fn logged(quiet: bool, rust_log: Option<&str>, emit: impl FnOnce()) -> String {
        let cap = Capture::default();
        let (f, _) = filter(quiet, rust_log);
        tracing::subscriber::with_default(subscriber(f, cap.clone()), emit);
        cap.text()
    }

    /// `[` seconds `s LEVEL ROLE] rest`, or None.
    fn parse(line: &str) -> Option<(f64, &str, &str)> {
        let inner = line.strip_prefix('[')?;
        let (head, rest) = inner.split_once("] ")?;
        let (t, head) = head.trim_start().split_once("s ")?;
        let (level, _role) = head.split_once(' ')?;
        Some((t.parse().ok()?, level, rest))
    }

    #[test]
    fn one_line_per_event_with_time_level_and_role() {
        let out = logged(false, None, || {
            tracing::info!(role = "coordinator", "{} workers: starting", 2);
            tracing::warn!(role = %format!("worker {}", "w-1"), "slow\nlink");
        });
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines.len(), 2, "{out}");
        assert!(lines[0].starts_with("[    0.0"), "{out}");
        assert!(
            lines[0].ends_with("s INFO coordinator] 2 workers: starting"),
            "{out}"
        );
        assert!(
            lines[1].ends_with("s WARN worker w-1] slow\\nlink"),
            "{out}"
        );
        let (t, level, rest) = parse(lines[0]).unwrap();
        assert!((0.0..5.0).contains(&t));
        assert_eq!((level, rest), ("INFO", "2 workers: starting"));
    }

    #[test]
    fn events_without_a_role_name_their_target_and_extra_fields_follow() {
        let out = logged(false, None, || {
            tracing::error!(target: "zenoh_transport", attempt = 3, "cannot connect");
            tracing::warn!(target: "zenoh", "Gossip is disabled");
        });
        assert!(
            out.trim_end()
                .ends_with("s ERROR zenoh_transport] cannot connect attempt=3"),
            "{out}"
        );
        assert!(
            !out.contains("Gossip"),
            "other crates only on errors: {out}"
        );
        let all = logged(false, Some("info,zenoh=warn"), || {
            tracing::warn!(target: "zenoh", "Gossip is disabled");
        });
        assert!(all.contains("WARN zenoh] Gossip"), "{all}");
    }

    #[test]
    fn quiet_keeps_warnings_and_rust_log_overrides_it() {
        let emit = || {
            tracing::info!(role = "coordinator", "joined");
            tracing::warn!(role = "coordinator", "refused");
        };
        let quiet = logged(true, None, emit);
        assert!(
            !quiet.contains("joined") && quiet.contains("refused"),
            "{quiet}"
        );
        let loud = logged(true, Some("info"), emit);
        assert!(
            loud.contains("joined") && loud.contains("refused"),
            "{loud}"
        );
        let off = logged(false, Some("fixplan_worker=error"), emit);
        assert_eq!(off, "");
        let blank = logged(false, Some("  "), emit);
        assert!(blank.contains("joined"), "{blank}");
    }

    #[test]
    fn a_bad_rust_log_falls_back_to_the_default() {
        let (_, bad) = filter(false, Some("fixplan_worker=loud"));
        assert!(bad.is_some());
        let out = logged(true, Some("fixplan_worker=loud"), || {
            tracing::info!(role = "coordinator", "joined");
            tracing::warn!(role = "coordinator", "refused");
        });
        assert!(!out.contains("joined") && out.contains("refused"), "{out}");
    }

    /// A writer like a standard error whose reader is gone.
    struct Closed;

    impl io::Write for Closed {
        fn write(&mut self, _: &[u8]) -> io::Result<usize> {
            Err(io::ErrorKind::BrokenPipe.into())
        }
        fn flush(&mut self) -> io::Result<()> {
            Err(io::ErrorKind::BrokenPipe.into())
        }
    }

    #[test]
    fn a_closed_writer_neither_panics_nor_stops_the_caller() {
        let (f, _) = filter(false, None);
        let s = subscriber(f, || Closed);
        let mut reached = false;
        tracing::subscriber::with_default(s, || {
            for i in 0..3 {
                tracing::warn!(role = "coordinator", "line {i}");
            }
            reached = true;
        });
        assert!(reached);
    }
}
