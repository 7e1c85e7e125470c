//! `fixplan certs`: a certificate authority and the certificates of mutual
//! TLS between a coordinator, its workers and a zenoh router (ECDSA P-256,
//! PEM files). Access control matches on the common names
//! [`COORDINATOR_CN`] and [`WORKER_CN`] (`deploy/zenoh/router.json5`).

use rcgen::{
    BasicConstraints, CertificateParams, DnType, ExtendedKeyUsagePurpose, IsCa, Issuer, KeyPair,
    KeyUsagePurpose,
};
use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime, UNIX_EPOCH};
use thiserror::Error;

/// The common name of the coordinator's certificate.
pub const COORDINATOR_CN: &str = "fixplan-coordinator";
/// The common name of every worker's certificate.
pub const WORKER_CN: &str = "fixplan-worker";
/// The common name of a zenoh router's certificate.
pub const ROUTER_CN: &str = "fixplan-router";

/// Why certificates could not be made or written.
#[derive(Debug, Error)]
pub enum CertError {
    /// rcgen refused a name or could not sign.
    #[error("certificate: {0}")]
    Rcgen(#[from] rcgen::Error),
    /// A time before 1970 or too far ahead.
    #[error("certificate validity out of range")]
    Validity,
    /// A file could not be written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The directory already holds a CA: not overwritten (its certificates
    /// would all stop working).
    #[error("{} exists: not overwriting a certificate authority", path.display())]
    Exists {
        /// The CA certificate found.
        path: PathBuf,
    },
}

/// When a certificate is valid.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Validity {
    /// Valid from.
    pub not_before: SystemTime,
    /// Valid until.
    pub not_after: SystemTime,
}

impl Validity {
    /// From an hour ago (clocks differ a little) for `days` days.
    pub fn days(days: u64) -> Validity {
        let now = SystemTime::now();
        Validity {
            not_before: now - Duration::from_secs(3600),
            not_after: now + Duration::from_secs(days * 86_400),
        }
    }

    fn apply(&self, params: &mut CertificateParams) -> Result<(), CertError> {
        let at = |t: SystemTime| -> Result<_, CertError> {
            let since = t
                .duration_since(UNIX_EPOCH)
                .map_err(|_| CertError::Validity)?;
            Ok(rcgen::date_time_ymd(1970, 1, 1) + since)
        };
        params.not_before = at(self.not_before)?;
        params.not_after = at(self.not_after)?;
        Ok(())
    }
}

/// A certificate and its private key, PEM encoded.
#[derive(Debug, Clone)]
pub struct Issued {
    /// The certificate.
    pub cert_pem: String,
    /// Its private key (PKCS#8).
    pub key_pem: String,
}

/// A certificate authority that signs the others.
pub struct Authority {
    issuer: Issuer<'static, KeyPair>,
    /// The CA's own certificate and key.
    pub own: Issued,
}

impl Authority {
    /// A new self-signed CA named `name`.
    pub fn new(name: &str, validity: Validity) -> Result<Authority, CertError> {
        let key = KeyPair::generate()?;
        let mut p = CertificateParams::new(Vec::<String>::new())?;
        p.distinguished_name.push(DnType::CommonName, name);
        p.is_ca = IsCa::Ca(BasicConstraints::Unconstrained);
        p.key_usages = vec![
            KeyUsagePurpose::KeyCertSign,
            KeyUsagePurpose::CrlSign,
            KeyUsagePurpose::DigitalSignature,
        ];
        validity.apply(&mut p)?;
        let cert = p.self_signed(&key)?;
        let own = Issued {
            cert_pem: cert.pem(),
            key_pem: key.serialize_pem(),
        };
        Ok(Authority {
            issuer: Issuer::new(p, key),
            own,
        })
    }

    /// A certificate for `common_name`, valid for the host names and
    /// addresses `hosts` (checked by whoever connects to it), usable by a
    /// TLS server and client alike.
    pub fn issue(
        &self,
        common_name: &str,
        hosts: &[String],
        validity: Validity,
    ) -> Result<Issued, CertError> {
        let key = KeyPair::generate()?;
        let mut p = CertificateParams::new(hosts.to_vec())?;
        p.distinguished_name.push(DnType::CommonName, common_name);
        p.key_usages = vec![
            KeyUsagePurpose::DigitalSignature,
            KeyUsagePurpose::KeyEncipherment,
        ];
        p.extended_key_usages = vec![
            ExtendedKeyUsagePurpose::ServerAuth,
            ExtendedKeyUsagePurpose::ClientAuth,
        ];
        p.use_authority_key_identifier_extension = true;
        validity.apply(&mut p)?;
        let cert = p.signed_by(&key, &self.issuer)?;
        Ok(Issued {
            cert_pem: cert.pem(),
            key_pem: key.serialize_pem(),
        })
    }
}

/// What `fixplan certs` makes.
#[derive(Debug, Clone)]
pub struct CertsOptions {
    /// Where the files go (created if needed).
    pub dir: PathBuf,
    /// Worker certificates to make (`worker-1.pem`...).
    pub workers: usize,
    /// Names and addresses of the coordinator and router hosts, besides
    /// `localhost`, `127.0.0.1` and `::1`.
    pub hosts: Vec<String>,
    /// Days the certificates are valid.
    pub days: u64,
}

/// Writes `path` (private keys readable by the owner only).
fn write(path: &Path, text: &str, private: bool) -> Result<(), CertError> {
    let io = |source| CertError::Io {
        path: path.to_path_buf(),
        source,
    };
    let mut o = std::fs::OpenOptions::new();
    o.write(true).create(true).truncate(true);
    #[cfg(unix)]
    if private {
        use std::os::unix::fs::OpenOptionsExt;
        o.mode(0o600);
    }
    #[cfg(not(unix))]
    let _ = private;
    let mut f = o.open(path).map_err(io)?;
    std::io::Write::write_all(&mut f, text.as_bytes()).map_err(io)
}

/// Writes `NAME.pem` and `NAME-key.pem` in `dir`.
fn write_pair(dir: &Path, name: &str, issued: &Issued) -> Result<[PathBuf; 2], CertError> {
    let cert = dir.join(format!("{name}.pem"));
    let key = dir.join(format!("{name}-key.pem"));
    write(&cert, &issued.cert_pem, false)?;
    write(&key, &issued.key_pem, true)?;
    Ok([cert, key])
}

/// Makes a CA (`ca.pem`, `ca-key.pem`), the coordinator's and a router's
/// certificates (`coordinator.pem`, `router.pem` and keys) and `workers`
/// worker certificates (`worker-N.pem` and keys) in `o.dir`; returns the
/// files written. Refuses a directory that already has a `ca.pem`.
pub fn write_certs(opts: &CertsOptions) -> Result<Vec<PathBuf>, CertError> {
    let ca_path = opts.dir.join("ca.pem");
    if ca_path.exists() {
        return Err(CertError::Exists { path: ca_path });
    }
    std::fs::create_dir_all(&opts.dir).map_err(|source| CertError::Io {
        path: opts.dir.clone(),
        source,
    })?;
    let validity = Validity::days(opts.days);
    let ca = Authority::new("fixplan-ca", validity)?;
    let mut files = write_pair(&opts.dir, "ca", &ca.own)?.to_vec();
    let mut hosts: Vec<String> = ["localhost", "127.0.0.1", "::1"]
        .iter()
        .map(|h| h.to_string())
        .collect();
    hosts.extend(opts.hosts.iter().cloned());
    for (name, cn) in [("coordinator", COORDINATOR_CN), ("router", ROUTER_CN)] {
        let c = ca.issue(cn, &hosts, validity)?;
        files.extend(write_pair(&opts.dir, name, &c)?);
    }
    for n in 1..=opts.workers {
        let c = ca.issue(WORKER_CN, &[WORKER_CN.to_string()], validity)?;
        files.extend(write_pair(&opts.dir, &format!("worker-{n}"), &c)?);
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_a_ca_and_refuses_to_overwrite_it() {
        let dir = std::env::temp_dir().join(fixplan_worker::host::unique_name("certs"));
        let o = CertsOptions {
            dir: dir.clone(),
            workers: 2,
            hosts: vec!["coord.example".into()],
            days: 30,
        };
        let files = write_certs(&o).unwrap();
        assert_eq!(files.len(), 2 * 5);
        let ca = std::fs::read_to_string(dir.join("ca.pem")).unwrap();
        assert!(ca.starts_with("-----BEGIN CERTIFICATE-----"), "{ca}");
        let key = std::fs::read_to_string(dir.join("worker-2-key.pem")).unwrap();
        assert!(key.starts_with("-----BEGIN PRIVATE KEY-----"), "{key}");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = std::fs::metadata(dir.join("ca-key.pem"))
                .unwrap()
                .permissions()
                .mode();
            assert_eq!(mode & 0o077, 0, "{mode:o}");
        }
        assert!(matches!(write_certs(&o), Err(CertError::Exists { .. })));
        std::fs::remove_dir_all(dir).unwrap();
    }
}
