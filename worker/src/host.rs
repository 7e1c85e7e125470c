//! Who and where a process is: the host id that tells the coordinator a
//! worker shares its shared memory, and unique worker names.

use sha2::{Digest, Sha256};
use std::os::unix::fs::MetadataExt;
use std::time::{SystemTime, UNIX_EPOCH};

fn read_trim(path: &str) -> String {
    std::fs::read_to_string(path)
        .map(|s| s.trim().to_string())
        .unwrap_or_default()
}

/// The host name, or `host` when it cannot be read.
pub fn hostname() -> String {
    let h = read_trim("/proc/sys/kernel/hostname");
    if h.is_empty() {
        "host".into()
    } else {
        h
    }
}

/// An id shared by exactly the processes that can meet in the same
/// `/dev/shm`: host name, boot id and the device and inode of `/dev/shm`
/// (a container or pod with its own `/dev/shm` gets its own id).
pub fn host_id() -> String {
    let mut h = Sha256::new();
    h.update(hostname());
    h.update(read_trim("/proc/sys/kernel/random/boot_id"));
    if let Ok(m) = std::fs::metadata("/dev/shm") {
        h.update(m.dev().to_le_bytes());
        h.update(m.ino().to_le_bytes());
    }
    h.finalize()[..8]
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Characters allowed in a key-expression chunk and an iceoryx2 name.
pub fn sanitize(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// A name unique across hosts and restarts: `host-pid-nonce`.
pub fn unique_name(kind: &str) -> String {
    let nanos = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or(0);
    let mut h = Sha256::new();
    h.update(nanos.to_le_bytes());
    h.update(std::process::id().to_le_bytes());
    h.update(host_id());
    let nonce: String = h.finalize()[..3]
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    format!(
        "{kind}-{}-{}-{nonce}",
        sanitize(&hostname()),
        std::process::id()
    )
}
