//! zenoh: session configuration, key expressions, and request/reply over
//! queries (a `get` with the encoded message as payload; the coordinator's
//! queryable replies with one encoded message).
//!
//! Key expressions under the run's prefix `P` (default `fixplan`):
//! - `P/join`: queryable of the coordinator; [`crate::protocol::Msg::Join`] -> `Welcome`/refusal;
//! - `P/work`: queryable of the coordinator; `Report` -> `Reply`;
//! - `P/alive/WORKER`: liveliness token of each worker;
//! - `P/coordinator`: liveliness token of the coordinator.

use crate::protocol::{decode, DecodeError, Frame};
use std::path::PathBuf;
use std::time::Duration;
use thiserror::Error;
use zenoh::Wait;

/// How to reach the others.
#[derive(Debug, Clone, Default)]
pub struct ZenohOptions {
    /// `peer` (default) or `client` (through a zenoh router).
    pub mode: Option<String>,
    pub listen: Vec<String>,
    pub connect: Vec<String>,
    /// A zenoh configuration file (JSON5): TLS, access control, routers.
    /// `listen`/`connect` given on the command line override its endpoints.
    pub config_file: Option<PathBuf>,
}

#[derive(Debug, Error)]
pub enum LinkError {
    #[error("zenoh configuration: {0}")]
    Config(String),
    #[error("zenoh: {0}")]
    Zenoh(String),
    #[error("iceoryx2: {0}")]
    Iceoryx2(String),
    #[error("no reply from the coordinator")]
    NoReply,
    #[error("unreadable reply: {0}")]
    Decode(#[from] DecodeError),
}

fn json_list(v: &[String]) -> String {
    let items: Vec<String> = v.iter().map(|s| format!("{s:?}")).collect();
    format!("[{}]", items.join(","))
}

/// A zenoh configuration: the file if any, else defaults with multicast
/// scouting off (explicit endpoints only) and gossip off.
pub fn zenoh_config(o: &ZenohOptions) -> Result<zenoh::Config, LinkError> {
    let cfg_err = |e: zenoh::Error| LinkError::Config(e.to_string());
    let mut c = match &o.config_file {
        Some(p) => zenoh::Config::from_file(p)
            .map_err(|e| LinkError::Config(format!("{}: {e}", p.display())))?,
        None => {
            let mut c = zenoh::Config::default();
            c.insert_json5("scouting/multicast/enabled", "false")
                .map_err(cfg_err)?;
            c.insert_json5("scouting/gossip/enabled", "false")
                .map_err(cfg_err)?;
            c
        }
    };
    if let Some(m) = &o.mode {
        c.insert_json5("mode", &format!("{m:?}")).map_err(cfg_err)?;
    }
    if !o.listen.is_empty() || o.config_file.is_none() {
        c.insert_json5("listen/endpoints", &json_list(&o.listen))
            .map_err(cfg_err)?;
    }
    if !o.connect.is_empty() {
        c.insert_json5("connect/endpoints", &json_list(&o.connect))
            .map_err(cfg_err)?;
    }
    Ok(c)
}

pub fn open(o: &ZenohOptions) -> Result<zenoh::Session, LinkError> {
    let c = zenoh_config(o)?;
    zenoh::open(c)
        .wait()
        .map_err(|e| LinkError::Zenoh(e.to_string()))
}

/// Key expressions of one run.
#[derive(Debug, Clone)]
pub struct Keys {
    pub prefix: String,
}

impl Keys {
    pub fn new(prefix: &str) -> Keys {
        Keys {
            prefix: prefix.trim_end_matches('/').to_string(),
        }
    }
    pub fn join(&self) -> String {
        format!("{}/join", self.prefix)
    }
    pub fn work(&self) -> String {
        format!("{}/work", self.prefix)
    }
    pub fn alive(&self, worker: &str) -> String {
        format!("{}/alive/{worker}", self.prefix)
    }
    pub fn alive_all(&self) -> String {
        format!("{}/alive/*", self.prefix)
    }
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
        .map_err(|e| LinkError::Zenoh(e.to_string()))?;
    let reply = replies.recv().map_err(|_| LinkError::NoReply)?;
    match reply.result() {
        Ok(sample) => Ok(decode(&sample.payload().to_bytes())?),
        Err(e) => Err(LinkError::Zenoh(format!(
            "error reply: {}",
            String::from_utf8_lossy(&e.payload().to_bytes())
        ))),
    }
}
