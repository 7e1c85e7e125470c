//! zenoh: session configuration, key expressions, and request/reply over
//! queries (a `get` with the encoded message as payload; the coordinator's
//! queryable replies with one encoded message).
//!
//! Key expressions under the run's prefix `P` (default `fixplan`):
//! - `P/join`: queryable of the coordinator; [`crate::protocol::Msg::Join`] -> `Welcome`/refusal;
//! - `P/work`: queryable of the coordinator; `Report` -> `Reply`;
//! - `P/alive/WORKER`: liveliness token of each worker;
//! - `P/coordinator`: liveliness token of the coordinator.

use crate::protocol::{decode, DecodeError, EncodeError, Frame};
use std::path::PathBuf;
use std::time::Duration;
use thiserror::Error;
use zenoh::Wait;

/// How to reach the others.
#[derive(Debug, Clone, Default)]
pub struct ZenohOptions {
    /// Mutual TLS: the certificate files for `tls/...` endpoints (they
    /// fill `transport/link/tls` of the configuration, over a file's).
    pub tls: Option<TlsFiles>,
    /// Listen without TLS on addresses other hosts can reach (a trusted
    /// network): allowed, with a warning, instead of refused.
    pub insecure: bool,
    /// `peer` (default) or `client` (through a zenoh router).
    pub mode: Option<String>,
    /// Endpoints to listen on (`tcp/0.0.0.0:7447`): how the others reach a
    /// coordinator, or a worker in peer mode.
    pub listen: Vec<String>,
    /// Endpoints to connect to: a coordinator or a router.
    pub connect: Vec<String>,
    /// A zenoh configuration file (JSON5): TLS, access control, routers.
    /// `listen`/`connect` given on the command line override its endpoints.
    pub config_file: Option<PathBuf>,
}

/// The files of mutual TLS, PEM encoded.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TlsFiles {
    /// The certificate authority whose certificates are accepted.
    pub ca: PathBuf,
    /// This process's certificate and private key, shown on both sides of
    /// a link (listening and connecting). Without them a process can only
    /// connect to a listener that does not ask for client certificates.
    pub identity: Option<(PathBuf, PathBuf)>,
}

/// Why a request, or the link for it, failed. A worker keeps trying on
/// [`LinkError::NoReply`] and zenoh errors (the coordinator may not be up
/// yet) and stops on the others.
#[derive(Debug, Error)]
pub enum LinkError {
    /// The zenoh configuration options were refused.
    #[error("zenoh configuration: {0}")]
    Config(zenoh::Error),
    /// The zenoh configuration file cannot be read or was refused.
    #[error("zenoh configuration: {}: {detail}", path.display())]
    ConfigFile {
        /// The file given.
        path: PathBuf,
        /// zenoh's reason.
        detail: zenoh::Error,
    },
    /// A TLS file that cannot be read.
    #[error("TLS {what} {}: {source}", path.display())]
    TlsFile {
        /// `CA certificate`, `certificate` or `private key`.
        what: &'static str,
        /// The file given.
        path: PathBuf,
        /// Why it cannot be read.
        source: std::io::Error,
    },
    /// Listening where other hosts can join without TLS, and no
    /// `--insecure` (see [`crate::exposure`]).
    #[error(transparent)]
    Exposed(#[from] crate::exposure::Exposed),
    /// A zenoh session, query or token failed.
    #[error("zenoh: {0}")]
    Zenoh(zenoh::Error),
    /// The coordinator's queryable answered with an error instead of a
    /// frame (its text).
    #[error("zenoh: error reply: {0}")]
    ErrorReply(String),
    /// An iceoryx2 step failed: which one, and iceoryx2's error (the types
    /// differ per step, so it is kept as its debug text).
    #[error("iceoryx2: {step}: {detail}")]
    Iceoryx2 {
        /// The step (`node`, `open request-response service`, `loan`...).
        step: &'static str,
        /// iceoryx2's error.
        detail: String,
    },
    /// No reply in time: the coordinator is not (or no longer) there.
    #[error("no reply from the coordinator")]
    NoReply,
    /// A reply that is not a frame of this protocol version.
    #[error("unreadable reply: {0}")]
    Decode(#[from] DecodeError),
    /// The request could not be encoded.
    #[error(transparent)]
    Encode(#[from] EncodeError),
}

fn json_list(values: &[String]) -> String {
    let items: Vec<String> = values.iter().map(|s| format!("{s:?}")).collect();
    format!("[{}]", items.join(","))
}

/// A zenoh configuration: the file if any, else defaults with multicast
/// scouting off (explicit endpoints only) and gossip off.
pub fn zenoh_config(opts: &ZenohOptions) -> Result<zenoh::Config, LinkError> {
    let cfg_err = LinkError::Config;
    let mut c = match &opts.config_file {
        Some(p) => zenoh::Config::from_file(p).map_err(|detail| LinkError::ConfigFile {
            path: p.clone(),
            detail,
        })?,
        None => {
            let mut c = zenoh::Config::default();
            c.insert_json5("scouting/multicast/enabled", "false")
                .map_err(cfg_err)?;
            c.insert_json5("scouting/gossip/enabled", "false")
                .map_err(cfg_err)?;
            c
        }
    };
    if let Some(m) = &opts.mode {
        c.insert_json5("mode", &format!("{m:?}")).map_err(cfg_err)?;
    }
    if !opts.listen.is_empty() || opts.config_file.is_none() {
        c.insert_json5("listen/endpoints", &json_list(&opts.listen))
            .map_err(cfg_err)?;
    }
    if !opts.connect.is_empty() {
        c.insert_json5("connect/endpoints", &json_list(&opts.connect))
            .map_err(cfg_err)?;
    }
    if let Some(t) = &opts.tls {
        insert_tls(&mut c, t)?;
    }
    Ok(c)
}

/// A path as a JSON5 string.
fn json_path(file: &std::path::Path) -> String {
    serde_json::Value::String(file.display().to_string()).to_string()
}

/// Fills `transport/link/tls` from `t`, after checking the files can be
/// read (zenoh would only say so when a link is made).
fn insert_tls(config: &mut zenoh::Config, files: &TlsFiles) -> Result<(), LinkError> {
    let readable = |what: &'static str, path: &PathBuf| {
        std::fs::File::open(path)
            .map(drop)
            .map_err(|source| LinkError::TlsFile {
                what,
                path: path.clone(),
                source,
            })
    };
    readable("CA certificate", &files.ca)?;
    let mut keys = vec![("root_ca_certificate", json_path(&files.ca))];
    if let Some((cert, key)) = &files.identity {
        readable("certificate", cert)?;
        readable("private key", key)?;
        for (k, path) in [
            ("listen_certificate", cert),
            ("listen_private_key", key),
            ("connect_certificate", cert),
            ("connect_private_key", key),
        ] {
            keys.push((k, json_path(path)));
        }
    }
    let mtls = if files.identity.is_some() {
        "true"
    } else {
        "false"
    };
    keys.push(("enable_mtls", mtls.into()));
    keys.push(("verify_name_on_connect", "true".into()));
    for (k, v) in keys {
        config
            .insert_json5(&format!("transport/link/tls/{k}"), &v)
            .map_err(LinkError::Config)?;
    }
    Ok(())
}

/// Opens a session with [`zenoh_config`]: blocking, no async runtime
/// needed (zenoh runs its own). Listening where other hosts can join
/// without TLS is refused unless `o.insecure` (then a warning).
pub fn open(opts: &ZenohOptions) -> Result<zenoh::Session, LinkError> {
    let c = zenoh_config(opts)?;
    let exposed = crate::exposure::check_config(&c, opts.insecure)?;
    for e in exposed {
        tracing::warn!(
            role = "zenoh",
            "listening on {e} without TLS (--insecure): any host that reaches it can join"
        );
    }
    zenoh::open(c).wait().map_err(LinkError::Zenoh)
}

/// Key expressions of one run.
#[derive(Debug, Clone)]
pub struct Keys {
    /// The run's prefix without a trailing `/`: runs with different prefixes
    /// share a zenoh network without meeting.
    pub prefix: String,
}

impl Keys {
    /// Keys under `prefix` (a trailing `/` is ignored).
    pub fn new(prefix: &str) -> Keys {
        Keys {
            prefix: prefix.trim_end_matches('/').to_string(),
        }
    }
    /// The coordinator's queryable for [`crate::protocol::Msg::Join`].
    pub fn join(&self) -> String {
        format!("{}/join", self.prefix)
    }
    /// The coordinator's queryable for reports over zenoh.
    pub fn work(&self) -> String {
        format!("{}/work", self.prefix)
    }
    /// A worker's liveliness token: its loss re-queues the worker's shards.
    pub fn alive(&self, worker: &str) -> String {
        format!("{}/alive/{worker}", self.prefix)
    }
    /// Every worker's liveliness token, for the coordinator's subscriber.
    pub fn alive_all(&self) -> String {
        format!("{}/alive/*", self.prefix)
    }
    /// The coordinator's liveliness token.
    pub fn coordinator(&self) -> String {
        format!("{}/coordinator", self.prefix)
    }
}

/// Sends one encoded message as a query and decodes the first reply.
pub fn request(
    session: &zenoh::Session,
    key: &str,
    bytes: Vec<u8>,
    timeout: Duration,
) -> Result<Frame, LinkError> {
    let replies = session
        .get(key)
        .payload(bytes)
        .timeout(timeout)
        .wait()
        .map_err(LinkError::Zenoh)?;
    let reply = replies.recv().map_err(|_| LinkError::NoReply)?;
    match reply.result() {
        Ok(sample) => Ok(decode(&sample.payload().to_bytes())?),
        Err(e) => Err(LinkError::ErrorReply(
            String::from_utf8_lossy(&e.payload().to_bytes()).into_owned(),
        )),
    }
}
