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
//!
//! Links that TLS refused are the exception: zenoh tells them at debug
//! level among much routine, and they are what an operator must see (a
//! worker without a valid certificate, one presenting a wrong one). With
//! the default filter these events ([`LINK_REFUSALS`]) are shown as
//! warnings, and the rest of their targets' debug events are not.

use std::fmt::{self, Write as _};
use std::time::Instant;
use tracing::field::{Field, Visit};
use tracing::{Event, Level, Subscriber};
use tracing_subscriber::filter::ParseError;
use tracing_subscriber::fmt::format::Writer;
use tracing_subscriber::fmt::{FmtContext, FormatEvent, FormatFields, MakeWriter};
use tracing_subscriber::layer::{Context, Layer, SubscriberExt};
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

/// zenoh's events that tell of a link refused by TLS, shown with the
/// default filter: (target, start of the message, level zenoh gives it).
/// The first is a connecting side's, at debug among routine retries
/// (`Unable to connect to configured peer tls/...! received fatal alert:
/// CertificateRequired ...`), shown as a warning; the second a listener's
/// warnings (`peer sent no certificates`, `invalid peer certificate:
/// UnknownIssuer`...), which zenoh ends with a hint about open files that
/// fits only the other failure of that path (the log says `TLS handshake refused: ...` instead).
pub const LINK_REFUSALS: [(&str, &str, &str); 2] = [
    (
        "zenoh::net::runtime::orchestrator",
        "Unable to connect",
        "debug",
    ),
    ("zenoh_link_tls", "", "warn"),
];

/// The hint zenoh's TLS listener adds to every failed accept.
const OPEN_FILES_HINT: &str = ". Hint: increase the system open file limit.";

/// The filter directives used when `RUST_LOG` is unset or empty.
pub fn default_directives(quiet: bool) -> String {
    let level = if quiet { "warn" } else { "info" };
    let mut d = String::from("error");
    for c in OURS {
        d.push_str(&format!(",{c}={level}"));
    }
    for (target, _, level) in LINK_REFUSALS {
        d.push_str(&format!(",{target}={level}"));
    }
    d
}

/// Whether `target` is `module` or inside it.
fn within(target: &str, module: &str) -> bool {
    target
        .strip_prefix(module)
        .is_some_and(|rest| rest.is_empty() || rest.starts_with("::"))
}

/// For an event below error level from a target of [`LINK_REFUSALS`]:
/// the start of the messages shown (as warnings).
fn refusal_target(event: &Event<'_>) -> Option<&'static str> {
    let m = event.metadata();
    if *m.level() <= Level::ERROR {
        return None;
    }
    LINK_REFUSALS
        .iter()
        .find(|(t, _, _)| within(m.target(), t))
        .map(|(_, start, _)| *start)
}

/// A TLS listener's failed accept says so, instead of zenoh's hint about
/// open files, unless that is the cause.
fn tidy_message<'a>(target: &str, message: &'a str) -> std::borrow::Cow<'a, str> {
    match message.strip_suffix(OPEN_FILES_HINT) {
        Some(m) if within(target, "zenoh_link_tls") && !m.contains("open files") => {
            format!("TLS handshake refused: {m}").into()
        }
        _ => message.into(),
    }
}

/// Lets through, of the [`LINK_REFUSALS`] targets' events below error, only
/// the refusals.
struct LinkRefusals;

impl<S: Subscriber> Layer<S> for LinkRefusals {
    fn event_enabled(&self, event: &Event<'_>, _ctx: Context<'_, S>) -> bool {
        let Some(start) = refusal_target(event) else {
            return true;
        };
        let mut f = EventFields::default();
        event.record(&mut f);
        f.message.starts_with(start)
    }
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
    /// [`LINK_REFUSALS`] events are written as warnings.
    refusals_as_warnings: bool,
}

impl LineFormat {
    /// Times lines from now.
    pub fn new() -> LineFormat {
        LineFormat {
            start: Instant::now(),
            refusals_as_warnings: false,
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
struct EventFields {
    message: String,
    role: Option<String>,
    rest: String,
}

impl Visit for EventFields {
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
        let mut f = EventFields::default();
        event.record(&mut f);
        let meta = event.metadata();
        let role = f.role.as_deref().unwrap_or(meta.target());
        let t = self.start.elapsed().as_secs_f64();
        let level = match refusal_target(event) {
            Some(_) if self.refusals_as_warnings => Level::WARN,
            _ => *meta.level(),
        };
        write!(w, "[{t:9.3}s {level} ")?;
        write_one_line(&mut w, role)?;
        w.write_str("] ")?;
        write_one_line(&mut w, &tidy_message(meta.target(), &f.message))?;
        write_one_line(&mut w, &f.rest)?;
        w.write_char('\n')
    }
}

/// The subscriber of a process: `filter` and [`LineFormat`] lines on
/// `writer`; with `default` (the filter is [`default_directives`]), link
/// refusals are sorted out of their targets' debug events and shown as
/// warnings. Write errors are dropped, not reported: a closed standard
/// error (`fixplan run 2>&1 | head`) must neither panic nor stop a worker
/// or the coordinator in the middle of a run.
pub fn subscriber<W>(filter: EnvFilter, default: bool, writer: W) -> impl Subscriber + Send + Sync
where
    W: for<'a> MakeWriter<'a> + Send + Sync + 'static,
{
    let format = LineFormat {
        refusals_as_warnings: default,
        ..LineFormat::new()
    };
    let lines = tracing_subscriber::fmt::layer()
        .event_format(format)
        .with_ansi(false)
        .with_writer(writer)
        .log_internal_errors(false);
    tracing_subscriber::registry()
        .with(filter)
        .with(default.then_some(LinkRefusals))
        .with(lines)
}

/// Installs the process's subscriber: lines on standard error, filtered by
/// `RUST_LOG` or else by the default of `quiet` ([`default_directives`]).
/// For the command line's `main`; a second call changes nothing.
pub fn init(quiet: bool) {
    let rust_log = std::env::var("RUST_LOG").ok();
    let (filter, bad) = filter(quiet, rust_log.as_deref());
    let default = bad.is_some() || rust_log.as_deref().is_none_or(|s| s.trim().is_empty());
    let installed =
        tracing::subscriber::set_global_default(subscriber(filter, default, std::io::stderr));
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
        let s = subscriber(f, rust_log.is_none(), cap.clone());
        tracing::subscriber::with_default(s, emit);
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
    fn link_refusals_are_warnings_and_other_link_debug_is_not_shown() {
        let emit = || {
            tracing::debug!(
                target: "zenoh::net::runtime::orchestrator",
                "Unable to connect to configured peer tls/127.0.0.1:7447! received fatal alert: CertificateRequired"
            );
            tracing::debug!(target: "zenoh::net::runtime::orchestrator", "Try to connect");
            tracing::warn!(
                target: "zenoh::net::runtime::orchestrator",
                "Scouting delay elapsed before start conditions are met."
            );
            tracing::warn!(
                target: "zenoh_link_tls::unicast",
                "peer sent no certificates. Hint: increase the system open file limit."
            );
            tracing::debug!(target: "zenoh_link_tls::utils", "Loading user-generated certificates.");
        };
        let out = logged(true, None, emit);
        assert_eq!(out.lines().count(), 2, "{out}");
        assert!(
            out.contains("s WARN zenoh::net::runtime::orchestrator] Unable to connect"),
            "{out}"
        );
        assert!(
            out.contains("s WARN zenoh_link_tls::unicast] TLS handshake refused: peer sent no certificates\n"),
            "{out}"
        );
        let raw = logged(false, Some("zenoh_link_tls=debug"), emit);
        assert_eq!(raw.lines().count(), 2, "{raw}");
        assert!(
            raw.contains("DEBUG zenoh_link_tls::utils] Loading"),
            "{raw}"
        );
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
        let s = subscriber(f, true, || Closed);
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
