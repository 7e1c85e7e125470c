//! Safe defaults for listening: whoever reaches a coordinator's endpoint
//! can join its run and send results, so an endpoint that other hosts can
//! reach must be mutual TLS (`tls/...` with client certificates), unless
//! the operator says the network is trusted (`--insecure`).
//!
//! Loopback addresses (`127.0.0.0/8`, `::1`, `localhost`) and unix sockets
//! are only reachable from this host and need no TLS.

use std::net::IpAddr;
use thiserror::Error;

/// Who can reach a listen endpoint, and whether they must prove who they
/// are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reach {
    /// This host only: a unix socket or a loopback address.
    Local,
    /// Other hosts, over TLS that asks for a client certificate of the CA.
    MutualTls,
    /// Other hosts, over TLS without client certificates: anyone can join.
    TlsWithoutClientCerts,
    /// Other hosts, in plain text (`tcp`, `udp`, `ws`...): anyone can join.
    Plain,
}

impl Reach {
    /// What an endpoint that lets anyone join lacks, for messages.
    pub fn lacking(self) -> &'static str {
        match self {
            Reach::TlsWithoutClientCerts => "without client certificates",
            _ => "without TLS",
        }
    }
}

/// A listen endpoint that lets any host join, refused without `--insecure`.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error(
    "refusing to listen on {endpoint} {}: any host that reaches it could join the run \
     and send results. Listen on tls/HOST:PORT with --tls-ca, --tls-cert and --tls-key \
     (mutual TLS; `fixplan certs` makes the files), or on a loopback address or a unix \
     socket, or give --insecure on a trusted network",
    .reach.lacking()
)]
pub struct Exposed {
    /// The endpoint as configured.
    pub endpoint: String,
    /// How it is exposed ([`Reach::Plain`] or
    /// [`Reach::TlsWithoutClientCerts`]).
    pub reach: Reach,
}

/// Whether `host` (an address or name without port) is this host only.
fn is_loopback_host(host: &str) -> bool {
    let h = host.trim_start_matches('[').trim_end_matches(']');
    h.eq_ignore_ascii_case("localhost") || h.parse::<IpAddr>().is_ok_and(|ip| ip.is_loopback())
}

/// The host part of a zenoh locator address (`127.0.0.1:7447`,
/// `[::1]:0`, `name:7447`).
fn host_of(address: &str) -> &str {
    if let Some(rest) = address.strip_prefix('[') {
        return rest.split(']').next().unwrap_or(rest);
    }
    address.rsplit_once(':').map_or(address, |(h, _)| h)
}

/// Who can reach `endpoint` (`PROTOCOL/ADDRESS[?metadata][#config]`);
/// `mtls`: the configuration asks TLS clients for a certificate.
pub fn reach(endpoint: &str, mtls: bool) -> Reach {
    let locator = endpoint.split(['#', '?']).next().unwrap_or(endpoint);
    let (proto, address) = locator.split_once('/').unwrap_or((locator, ""));
    match proto {
        "unixsock-stream" | "unixpipe" => Reach::Local,
        _ if is_loopback_host(host_of(address)) => Reach::Local,
        "tls" | "quic" if mtls => Reach::MutualTls,
        "tls" | "quic" => Reach::TlsWithoutClientCerts,
        _ => Reach::Plain,
    }
}

/// The decision for a process's listen endpoints: an [`Exposed`] error for
/// the first that lets any host join, or, with `insecure`, the list of
/// those endpoints (to warn about).
pub fn check_listen(
    endpoints: &[String],
    mtls: bool,
    insecure: bool,
) -> Result<Vec<String>, Exposed> {
    let mut open = Vec::new();
    for e in endpoints {
        let r = reach(e, mtls);
        if matches!(r, Reach::Plain | Reach::TlsWithoutClientCerts) {
            if !insecure {
                return Err(Exposed {
                    endpoint: e.clone(),
                    reach: r,
                });
            }
            open.push(e.clone());
        }
    }
    Ok(open)
}

/// The strings of a JSON list (none for anything else).
fn strings(value: &serde_json::Value) -> Vec<String> {
    value
        .as_array()
        .map(|a| {
            a.iter()
                .filter_map(|e| e.as_str().map(str::to_owned))
                .collect()
        })
        .unwrap_or_default()
}

/// The endpoints a configuration listens on in its mode (zenoh's default
/// mode is `peer`; a mode-dependent value lists them per mode).
fn listen_endpoints(config: &zenoh::Config) -> Vec<String> {
    let json = |k: &str| {
        config
            .get_json(k)
            .ok()
            .and_then(|s| serde_json::from_str::<serde_json::Value>(&s).ok())
    };
    let mode = json("mode")
        .and_then(|m| m.as_str().map(str::to_owned))
        .unwrap_or_else(|| "peer".into());
    match json("listen/endpoints") {
        Some(serde_json::Value::Object(per_mode)) => {
            per_mode.get(&mode).map(strings).unwrap_or_default()
        }
        Some(v) => strings(&v),
        None => Vec::new(),
    }
}

/// [`check_listen`] on a zenoh configuration's listen endpoints, with
/// its `transport/link/tls/enable_mtls`.
pub fn check_config(config: &zenoh::Config, insecure: bool) -> Result<Vec<String>, Exposed> {
    let mtls = config
        .get_json("transport/link/tls/enable_mtls")
        .is_ok_and(|v| v.trim() == "true");
    check_listen(&listen_endpoints(config), mtls, insecure)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loopback_and_unix_sockets_are_local() {
        for e in [
            "tcp/127.0.0.1:7447",
            "tcp/127.3.2.1:0",
            "tcp/[::1]:7447",
            "tcp/localhost:7447",
            "tcp/LOCALHOST:7447#iface=lo",
            "udp/127.0.0.1:7447",
            "tls/127.0.0.1:7447",
            "unixsock-stream//tmp/fixplan.sock",
            "unixpipe/fixplan",
        ] {
            assert_eq!(reach(e, false), Reach::Local, "{e}");
        }
    }

    #[test]
    fn other_addresses_are_plain_unless_mutual_tls() {
        for e in [
            "tcp/0.0.0.0:7447",
            "tcp/[::]:0",
            "tcp/10.0.0.5:7447",
            "tcp/coordinator.example:7447",
            "ws/0.0.0.0:8000",
            "tcp/128.0.0.1:7447",
        ] {
            assert_eq!(reach(e, true), Reach::Plain, "{e}");
        }
        assert_eq!(reach("tls/0.0.0.0:7447", true), Reach::MutualTls);
        assert_eq!(
            reach("tls/0.0.0.0:7447", false),
            Reach::TlsWithoutClientCerts
        );
    }

    #[test]
    fn open_endpoints_are_refused_without_insecure() {
        let eps = vec![
            "unixsock-stream//tmp/a.sock".to_string(),
            "tcp/0.0.0.0:7447".to_string(),
        ];
        let e = check_listen(&eps, true, false).unwrap_err();
        assert_eq!(e.endpoint, "tcp/0.0.0.0:7447");
        let text = e.to_string();
        assert!(
            text.starts_with("refusing to listen on tcp/0.0.0.0:7447 without TLS"),
            "{text}"
        );
        assert!(text.contains("--insecure"), "{text}");
        assert_eq!(
            check_listen(&eps, true, true).unwrap(),
            vec!["tcp/0.0.0.0:7447".to_string()]
        );
        let tls = vec!["tls/0.0.0.0:7447".to_string()];
        assert!(check_listen(&tls, true, false).unwrap().is_empty());
        let e = check_listen(&tls, false, false).unwrap_err();
        assert!(e.to_string().contains("without client certificates"), "{e}");
        assert!(check_listen(&[], false, false).unwrap().is_empty());
    }

    #[test]
    fn configurations_are_read_per_mode() {
        let mut c = zenoh::Config::default();
        // zenoh's default: peers listen on every interface.
        assert!(check_config(&c, false).is_err());
        c.insert_json5("mode", "\"client\"").unwrap();
        assert!(check_config(&c, false).unwrap().is_empty());
        c.insert_json5("mode", "\"peer\"").unwrap();
        c.insert_json5("listen/endpoints", r#"["tls/0.0.0.0:7447"]"#)
            .unwrap();
        assert!(check_config(&c, false).is_err());
        c.insert_json5("transport/link/tls/enable_mtls", "true")
            .unwrap();
        assert!(check_config(&c, false).unwrap().is_empty());
    }
}
