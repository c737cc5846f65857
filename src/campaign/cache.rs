//! The campaign's cache: each point's result (its JSON) under a SHA-256 digest of everything
//! it depends on, so a rerun recomputes only the points whose files or settings changed.

use std::io::Read;
use std::path::{Path, PathBuf};

use serde_json::Value as Json;
use sha2::{Digest, Sha256};

use crate::error::{Error, Result};
use crate::job::Job;

/// A folder of results by key.
pub(super) struct Cache {
    dir: PathBuf,
}

/// An I/O error on `path`.
fn io(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |e| Error::Io {
        path: crate::error::excerpt(&path.display().to_string()),
        message: e.to_string(),
    }
}

impl Cache {
    /// The cache in `dir`, made if missing.
    pub(super) fn open(dir: &Path) -> Result<Self> {
        std::fs::create_dir_all(dir).map_err(io(dir))?;
        Ok(Self {
            dir: dir.to_path_buf(),
        })
    }

    fn path(&self, key: &str) -> PathBuf {
        self.dir.join(format!("{key}.json"))
    }

    /// The result kept under `key`, if there is one that reads back (a damaged entry is
    /// recomputed, not trusted).
    pub(super) fn load(&self, key: &str) -> Option<Json> {
        let text = crate::limits::read_json_text(self.path(key)).ok()?;
        serde_json::from_str(&text).ok()
    }

    /// Keeps `json` under `key`: written beside, then renamed, so a reader never sees half.
    pub(super) fn store(&self, key: &str, json: &Json) -> Result<()> {
        let path = self.path(key);
        let tmp = self.dir.join(format!("{key}.json.tmp"));
        std::fs::write(&tmp, json.to_string()).map_err(io(&tmp))?;
        std::fs::rename(&tmp, &path).map_err(io(&path))
    }
}

/// The digest of a point: the crate's version, the job's options and channels, whether
/// per-line coefficients are kept, and each file's name and bytes.
///
/// # Errors
/// [`Error::Io`] for a file that cannot be read.
pub(super) fn key(job: &Job, files: &[PathBuf], per_frequency: bool) -> Result<String> {
    let mut h = Sha256::new();
    h.update(env!("CARGO_PKG_VERSION").as_bytes());
    h.update(
        format!(
            "{:?}\n{:?}\n{per_frequency}\n",
            job.options(),
            job.channels()
        )
        .as_bytes(),
    );
    let mut buf = vec![0u8; 1 << 16];
    for path in files {
        h.update(path.display().to_string().as_bytes());
        h.update([0]);
        let mut file = std::fs::File::open(path).map_err(io(path))?;
        let mut len = 0u64;
        loop {
            let n = file.read(&mut buf).map_err(io(path))?;
            if n == 0 {
                break;
            }
            len += n as u64;
            h.update(&buf[..n]);
        }
        h.update(len.to_le_bytes());
    }
    Ok(hex(&h.finalize()))
}

/// The key of a point chained with its baseline's.
pub(super) fn chain(own: &str, baseline: &str) -> String {
    let mut h = Sha256::new();
    h.update(own.as_bytes());
    h.update(b"\nbaseline\n");
    h.update(baseline.as_bytes());
    hex(&h.finalize())
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}
