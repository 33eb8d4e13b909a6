//! Checkpoints of long runs: a versioned, checksummed container written
//! atomically, and a small exact binary encoding for what goes in it.
//!
//! Why a container of its own: a run that is killed (Ctrl-C, SIGTERM, a
//! cluster's time limit, a full disk) must be able to continue *to the same
//! bits* as the run that was never interrupted, so every double is saved
//! as its 64 bits (never as decimal text), and a file that was cut short or
//! overwritten must be refused, never loaded into a run that would then go
//! on from a wrong state. The layout (all integers little-endian):
//!
//! ```text
//! offset  size  field
//!      0     8  magic "SYMLABCK"
//!      8     4  format version (FORMAT_VERSION)
//!     12     4  kind (1 cloth, 2 compare, 3 paper)
//!     16     8  payload length n
//!     24     4  CRC-32 (IEEE) of bytes 0..24 and of the payload
//!     28     n  payload
//! ```
//!
//! A file is written to a temporary file in the same directory, synced,
//! renamed over the old checkpoint and the directory synced, so that at
//! every moment the checkpoint on disk is either the old one or the new
//! one, whole.
//!
//! ```
//! use integrator_core::checkpoint::{self, Decoder, Encoder, Kind};
//!
//! let dir = std::env::temp_dir().join(format!("ckpt-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir)?;
//! let path = dir.join("checkpoint.symlab");
//! let mut e = Encoder::new();
//! e.f64s(&[0.1, -0.0, f64::MIN_POSITIVE]);
//! e.str("rattle");
//! checkpoint::write(&path, Kind::Cloth, &e.finish())?;
//!
//! let payload = checkpoint::read(&path, Kind::Cloth)?;
//! let mut d = Decoder::new(&path, &payload);
//! assert_eq!(d.f64s("state")?[1].to_bits(), (-0.0f64).to_bits());
//! assert_eq!(d.str("method")?, "rattle");
//! d.end()?;
//! # std::fs::remove_dir_all(&dir)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::fmt;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// The first eight bytes of every checkpoint.
pub const MAGIC: &[u8; 8] = b"SYMLABCK";
/// The version of the layout and of the payloads this build writes; a
/// file of another version is refused (the payloads hold a run's internal
/// state, which changes with the code that reads it).
// 2: a cloth checkpoint holds the run's request (`jobs::cloth`), no longer the
// command line's arguments. 3: the cloth's variable step keeps its last
// continuous count, not the last count (its search changed with it).
pub const FORMAT_VERSION: u32 = 3;
/// The name of a run's checkpoint in its output folder.
pub const FILE_NAME: &str = "checkpoint.symlab";
/// The header's length in bytes.
const HEADER: usize = 28;

/// What a checkpoint continues.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A `symlab cloth` run.
    Cloth,
    /// A `symlab compare` sweep.
    Compare,
    /// A `symlab paper` run.
    Paper,
}

impl Kind {
    fn code(self) -> u32 {
        match self {
            Kind::Cloth => 1,
            Kind::Compare => 2,
            Kind::Paper => 3,
        }
    }
    fn from_code(code: u32) -> Option<Kind> {
        match code {
            1 => Some(Kind::Cloth),
            2 => Some(Kind::Compare),
            3 => Some(Kind::Paper),
            _ => None,
        }
    }
    /// The kind's name, as the commands are named.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Cloth => "cloth",
            Kind::Compare => "compare",
            Kind::Paper => "paper",
        }
    }
}

impl fmt::Display for Kind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Why a checkpoint could not be written or read. Every message starts
/// with the file's path and says what is wrong with it.
#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    #[error("{}: cannot read the checkpoint: {source}", path.display())]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{}: cannot write the checkpoint: {source}", path.display())]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{}: not a symlab checkpoint (it does not start with \"SYMLABCK\")", path.display())]
    NotCheckpoint { path: PathBuf },
    #[error("{}: truncated checkpoint: {what}", path.display())]
    Truncated { path: PathBuf, what: String },
    #[error(
        "{}: corrupted checkpoint: its checksum is {found:08x}, its header says {expected:08x}",
        path.display()
    )]
    Checksum {
        path: PathBuf,
        found: u32,
        expected: u32,
    },
    #[error(
        "{}: checkpoint format version {found}; this symlab reads version {expected} only (finish the run with the symlab that started it)",
        path.display()
    )]
    Version {
        path: PathBuf,
        found: u32,
        expected: u32,
    },
    #[error("{}: a checkpoint of kind {found}, expected {expected}", path.display())]
    Kind {
        path: PathBuf,
        found: String,
        expected: Kind,
    },
    /// The container is sound but its payload does not decode (written by
    /// a different build of the same version, or a bug).
    #[error("{}: checkpoint payload: {what}", path.display())]
    Payload { path: PathBuf, what: String },
    /// The output folder cannot take a checkpoint (read-only, full).
    #[error("{}: the output directory is not writable: {source}", dir.display())]
    NotWritable {
        dir: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{}: cannot remove the checkpoint: {source}", path.display())]
    Remove {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

/// The container's bytes for `payload`.
pub fn encode(kind: Kind, payload: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(HEADER + payload.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&kind.code().to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    let mut crc = crc32fast::Hasher::new();
    crc.update(&out);
    crc.update(payload);
    out.extend_from_slice(&crc.finalize().to_le_bytes());
    out.extend_from_slice(payload);
    out
}

/// The kind and payload of a container's `bytes` read from `path` (named
/// in the errors), checked: magic, version, length and checksum.
pub fn decode(path: &Path, bytes: &[u8]) -> Result<(Kind, Vec<u8>), CheckpointError> {
    let path_buf = || path.to_path_buf();
    if bytes.len() < MAGIC.len() || &bytes[..MAGIC.len()] != MAGIC {
        if bytes.len() < MAGIC.len() && MAGIC.starts_with(bytes) {
            return Err(CheckpointError::Truncated {
                path: path_buf(),
                what: format!("{} bytes, shorter than its header ({HEADER})", bytes.len()),
            });
        }
        return Err(CheckpointError::NotCheckpoint { path: path_buf() });
    }
    if bytes.len() < HEADER {
        return Err(CheckpointError::Truncated {
            path: path_buf(),
            what: format!("{} bytes, shorter than its header ({HEADER})", bytes.len()),
        });
    }
    let u32_at = |i: usize| u32::from_le_bytes(bytes[i..i + 4].try_into().expect("4 bytes"));
    let version = u32_at(8);
    let code = u32_at(12);
    let len = u64::from_le_bytes(bytes[16..24].try_into().expect("8 bytes"));
    let expected_crc = u32_at(24);
    let have = (bytes.len() - HEADER) as u64;
    if have < len {
        return Err(CheckpointError::Truncated {
            path: path_buf(),
            what: format!("its header announces {len} bytes of payload, the file holds {have}"),
        });
    }
    let payload = &bytes[HEADER..];
    let mut crc = crc32fast::Hasher::new();
    crc.update(&bytes[..24]);
    crc.update(&payload[..len.min(have) as usize]);
    let found = crc.finalize();
    if have > len {
        return Err(CheckpointError::Payload {
            path: path_buf(),
            what: format!(
                "{} bytes after the {len} the header announces (something was appended)",
                have - len
            ),
        });
    }
    // The checksum covers the header too: a damaged version or kind field
    // reads as corruption, not as a file of another version.
    if found != expected_crc {
        return Err(CheckpointError::Checksum {
            path: path_buf(),
            found,
            expected: expected_crc,
        });
    }
    if version != FORMAT_VERSION {
        return Err(CheckpointError::Version {
            path: path_buf(),
            found: version,
            expected: FORMAT_VERSION,
        });
    }
    let kind = Kind::from_code(code).ok_or_else(|| CheckpointError::Kind {
        path: path_buf(),
        found: format!("{code} (unknown)"),
        expected: Kind::Cloth,
    })?;
    Ok((kind, payload.to_vec()))
}

/// Write `payload` as a checkpoint of `kind` to `path` atomically: a
/// temporary file beside it (its name starts with the checkpoint's),
/// written and synced, renamed over `path`, then the directory synced. On
/// an error the old checkpoint, if any, is left as it was.
pub fn write(path: &Path, kind: Kind, payload: &[u8]) -> Result<(), CheckpointError> {
    let bytes = encode(kind, payload);
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| FILE_NAME.to_string());
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let tmp = dir.join(format!("{name}.tmp-{}", std::process::id()));
    let werr = |p: &Path| {
        let p = p.to_path_buf();
        move |source| CheckpointError::Write { path: p, source }
    };
    let written = (|| {
        let mut file = std::fs::File::create(&tmp)?;
        file.write_all(&bytes)?;
        file.sync_all()
    })();
    if let Err(e) = written {
        let _ = std::fs::remove_file(&tmp);
        return Err(werr(&tmp)(e));
    }
    if let Err(e) = std::fs::rename(&tmp, path) {
        let _ = std::fs::remove_file(&tmp);
        return Err(werr(path)(e));
    }
    // The rename is durable once the directory is synced (where a
    // directory can be opened; not on every platform).
    if let Ok(d) = std::fs::File::open(dir) {
        let _ = d.sync_all();
    }
    Ok(())
}

/// The payload of the checkpoint at `path`, refused unless it is whole,
/// of this version and of `kind`.
pub fn read(path: &Path, kind: Kind) -> Result<Vec<u8>, CheckpointError> {
    let (found, payload) = read_any(path)?;
    if found != kind {
        return Err(CheckpointError::Kind {
            path: path.to_path_buf(),
            found: found.name().to_string(),
            expected: kind,
        });
    }
    Ok(payload)
}

/// The kind and payload of the checkpoint at `path`, of whichever kind.
pub fn read_any(path: &Path) -> Result<(Kind, Vec<u8>), CheckpointError> {
    let bytes = std::fs::read(path).map_err(|source| CheckpointError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    decode(path, &bytes)
}

/// An exact binary encoding of a payload: integers little-endian, doubles
/// as their bits, sequences with their length first. What is written is
/// read back in the same order by a [`Decoder`].
#[derive(Debug, Default)]
pub struct Encoder {
    buf: Vec<u8>,
}

impl Encoder {
    pub fn new() -> Encoder {
        Encoder::default()
    }
    pub fn u64(&mut self, x: u64) -> &mut Self {
        self.buf.extend_from_slice(&x.to_le_bytes());
        self
    }
    pub fn usize(&mut self, x: usize) -> &mut Self {
        self.u64(x as u64)
    }
    pub fn bool(&mut self, x: bool) -> &mut Self {
        self.buf.push(u8::from(x));
        self
    }
    /// A double as its 64 bits: NaN payloads and −0 survive.
    pub fn f64(&mut self, x: f64) -> &mut Self {
        self.u64(x.to_bits())
    }
    pub fn f64s(&mut self, xs: &[f64]) -> &mut Self {
        self.usize(xs.len());
        self.buf.reserve(8 * xs.len());
        for x in xs {
            self.buf.extend_from_slice(&x.to_bits().to_le_bytes());
        }
        self
    }
    pub fn bytes(&mut self, b: &[u8]) -> &mut Self {
        self.usize(b.len());
        self.buf.extend_from_slice(b);
        self
    }
    pub fn str(&mut self, s: &str) -> &mut Self {
        self.bytes(s.as_bytes())
    }
    pub fn finish(self) -> Vec<u8> {
        self.buf
    }
}

/// Reads what an [`Encoder`] wrote; every error names the file and the
/// field that could not be read.
#[derive(Debug)]
pub struct Decoder<'a> {
    path: &'a Path,
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Decoder<'a> {
    pub fn new(path: &'a Path, bytes: &'a [u8]) -> Decoder<'a> {
        Decoder {
            path,
            bytes,
            pos: 0,
        }
    }
    /// An error about the payload of this file.
    pub fn error(&self, what: impl Into<String>) -> CheckpointError {
        CheckpointError::Payload {
            path: self.path.to_path_buf(),
            what: what.into(),
        }
    }
    fn take(&mut self, n: usize, field: &str) -> Result<&'a [u8], CheckpointError> {
        let rest = self.bytes.len() - self.pos;
        if n > rest {
            return Err(self.error(format!(
                "{field}: needs {n} bytes at offset {}, {rest} remain",
                self.pos
            )));
        }
        let s = &self.bytes[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }
    pub fn u64(&mut self, field: &str) -> Result<u64, CheckpointError> {
        let b = self.take(8, field)?;
        Ok(u64::from_le_bytes(b.try_into().expect("8 bytes")))
    }
    pub fn usize(&mut self, field: &str) -> Result<usize, CheckpointError> {
        let x = self.u64(field)?;
        usize::try_from(x).map_err(|_| self.error(format!("{field}: {x} is too large")))
    }
    pub fn bool(&mut self, field: &str) -> Result<bool, CheckpointError> {
        match self.take(1, field)?[0] {
            0 => Ok(false),
            1 => Ok(true),
            b => Err(self.error(format!("{field}: {b} is not a boolean"))),
        }
    }
    pub fn f64(&mut self, field: &str) -> Result<f64, CheckpointError> {
        Ok(f64::from_bits(self.u64(field)?))
    }
    /// A length, checked against the bytes left (`unit` bytes per item)
    /// before anything is allocated.
    fn len(&mut self, unit: usize, field: &str) -> Result<usize, CheckpointError> {
        let n = self.usize(field)?;
        let rest = self.bytes.len() - self.pos;
        if n.checked_mul(unit).is_none_or(|b| b > rest) {
            return Err(self.error(format!(
                "{field}: {n} items of {unit} bytes announced, {rest} bytes remain"
            )));
        }
        Ok(n)
    }
    pub fn f64s(&mut self, field: &str) -> Result<Vec<f64>, CheckpointError> {
        let n = self.len(8, field)?;
        let b = self.take(8 * n, field)?;
        Ok(b.chunks_exact(8)
            .map(|c| f64::from_bits(u64::from_le_bytes(c.try_into().expect("8 bytes"))))
            .collect())
    }
    /// Doubles into `out`, which must have the saved length.
    pub fn f64s_into(&mut self, out: &mut [f64], field: &str) -> Result<(), CheckpointError> {
        let v = self.f64s(field)?;
        if v.len() != out.len() {
            return Err(self.error(format!(
                "{field}: {} values, this run has {}",
                v.len(),
                out.len()
            )));
        }
        out.copy_from_slice(&v);
        Ok(())
    }
    pub fn bytes(&mut self, field: &str) -> Result<&'a [u8], CheckpointError> {
        let n = self.len(1, field)?;
        self.take(n, field)
    }
    pub fn str(&mut self, field: &str) -> Result<&'a str, CheckpointError> {
        let b = self.bytes(field)?;
        std::str::from_utf8(b).map_err(|_| self.error(format!("{field}: not UTF-8")))
    }
    /// Everything was read: a payload with bytes left over is refused.
    pub fn end(&self) -> Result<(), CheckpointError> {
        let rest = self.bytes.len() - self.pos;
        if rest == 0 {
            Ok(())
        } else {
            Err(self.error(format!("{rest} bytes left over after the last field")))
        }
    }
}

/// How often a long run writes its checkpoint (`--checkpoint-every`,
/// Python's `checkpoint_every=`): never, or after at least this much wall
/// time (zero: after every frame or row).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Every {
    Off,
    After(std::time::Duration),
}

/// The default interval: runs shorter than this write none (unless a
/// signal stops them); a longer one loses at most this much.
pub const DEFAULT_EVERY: std::time::Duration = std::time::Duration::from_secs(60);

/// `30s`, `5m`, `1h`, `500ms`, a plain number of seconds, `0` (after
/// every frame) or `off`; the error says what was expected.
pub fn parse_every(text: &str) -> Result<Every, String> {
    let t = text.trim();
    if matches!(t, "off" | "never" | "none") {
        return Ok(Every::Off);
    }
    let split = t
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(t.len());
    let (number, unit) = t.split_at(split);
    let scale = match unit.trim() {
        "" | "s" => 1.0,
        "ms" => 1e-3,
        "m" | "min" => 60.0,
        "h" => 3600.0,
        other => {
            return Err(format!(
                "unknown unit \"{other}\" (expected e.g. 30s, 5m, 1h, 500ms, 0 for every frame, or off)"
            ));
        }
    };
    let x: f64 = number
        .parse()
        .map_err(|_| format!("\"{t}\" is not a duration (expected e.g. 30s, 5m, 1h, 0 or off)"))?;
    std::time::Duration::try_from_secs_f64(x * scale)
        .map(Every::After)
        .map_err(|_| format!("\"{t}\" is out of range"))
}

/// Refuse an output directory that cannot be written before a run
/// starts, naming it (a read-only or full file system), rather than
/// finding out at its first checkpoint.
pub fn check_writable(dir: &Path) -> Result<(), CheckpointError> {
    let probe = dir.join(format!(".symlab-write-test-{}", std::process::id()));
    let result = std::fs::write(&probe, b"symlab").and_then(|()| std::fs::remove_file(&probe));
    result.map_err(|source| {
        let _ = std::fs::remove_file(&probe);
        CheckpointError::NotWritable {
            dir: dir.to_path_buf(),
            source,
        }
    })
}

/// Remove a checkpoint (a finished run's, or an older run's in the folder
/// of a new one); none there is not an error. The temporaries of
/// [`write`](fn@write) beside it (`NAME.tmp-PID`) go too: a run killed while it
/// wrote one (SIGKILL, a power cut) leaves it behind, and it is never read,
/// so a finished run would otherwise keep a stray file its uninterrupted
/// twin does not have.
pub fn remove(path: &Path) -> Result<(), CheckpointError> {
    let gone = |p: &Path| match std::fs::remove_file(p) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(source) => Err(CheckpointError::Remove {
            path: p.to_path_buf(),
            source,
        }),
    };
    gone(path)?;
    let Some(name) = path.file_name().map(|n| n.to_string_lossy().into_owned()) else {
        return Ok(());
    };
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    // A folder that cannot be listed has no temporaries we could remove.
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(());
    };
    let prefix = format!("{name}.tmp-");
    for entry in entries.flatten() {
        let file = entry.file_name();
        let file = file.to_string_lossy();
        let stray = file
            .strip_prefix(&prefix)
            .is_some_and(|pid| !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()));
        if stray {
            gone(&entry.path())?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("symlab-ckpt-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn remove_takes_the_temporaries_a_killed_writer_left() {
        let dir = temp_dir("stray");
        let path = dir.join(FILE_NAME);
        write(&path, Kind::Paper, &sample()).unwrap();
        let stray = dir.join(format!("{FILE_NAME}.tmp-4242"));
        std::fs::write(&stray, b"half a checkpoint").unwrap();
        let keep = [
            dir.join(format!("{FILE_NAME}.tmp-")),
            dir.join(format!("{FILE_NAME}.tmp-12x")),
            dir.join("energy.csv"),
        ];
        for k in &keep {
            std::fs::write(k, b"not ours").unwrap();
        }
        remove(&path).unwrap();
        assert!(!path.exists());
        assert!(!stray.exists(), "the stray temporary is removed");
        for k in &keep {
            assert!(k.exists(), "{} is not a temporary of write", k.display());
        }
        // Nothing there is not an error.
        remove(&path).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
    }

    fn sample() -> Vec<u8> {
        let mut e = Encoder::new();
        e.u64(7)
            .f64s(&[1.0, 0.1, -0.0, f64::NAN, f64::INFINITY, 5e-324])
            .str("hammock")
            .bool(true);
        e.finish()
    }

    #[test]
    fn round_trip_keeps_every_bit() {
        let dir = temp_dir("round");
        let path = dir.join(FILE_NAME);
        write(&path, Kind::Cloth, &sample()).unwrap();
        let payload = read(&path, Kind::Cloth).unwrap();
        let mut d = Decoder::new(&path, &payload);
        assert_eq!(d.u64("n").unwrap(), 7);
        let xs = d.f64s("xs").unwrap();
        let want = [1.0, 0.1, -0.0, f64::NAN, f64::INFINITY, 5e-324];
        assert_eq!(xs.len(), want.len());
        for (a, b) in xs.iter().zip(want) {
            assert_eq!(a.to_bits(), b.to_bits());
        }
        assert_eq!(d.str("name").unwrap(), "hammock");
        assert!(d.bool("flag").unwrap());
        d.end().unwrap();
        // No temporary file is left behind.
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from(FILE_NAME)]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn every_truncation_is_refused_naming_the_file() {
        let bytes = encode(Kind::Compare, &sample());
        let path = Path::new("out/x/checkpoint.symlab");
        for n in 0..bytes.len() {
            let err = decode(path, &bytes[..n]).unwrap_err();
            let msg = err.to_string();
            assert!(msg.starts_with("out/x/checkpoint.symlab: "), "{msg}");
            assert!(
                matches!(err, CheckpointError::Truncated { .. }),
                "{n} bytes: {msg}"
            );
        }
        assert!(decode(path, &bytes).is_ok());
    }

    #[test]
    fn every_flipped_bit_is_refused() {
        let bytes = encode(Kind::Cloth, &sample());
        let path = Path::new("c/checkpoint.symlab");
        for i in 0..bytes.len() {
            for bit in 0..8 {
                let mut b = bytes.clone();
                b[i] ^= 1 << bit;
                let err = decode(path, &b).expect_err("a damaged file must be refused");
                assert!(err.to_string().starts_with("c/checkpoint.symlab: "));
            }
        }
    }

    #[test]
    fn garbage_and_appended_bytes_are_refused() {
        let path = Path::new("checkpoint.symlab");
        let err = decode(path, b"garbage written over the file, nothing else").unwrap_err();
        assert!(
            matches!(err, CheckpointError::NotCheckpoint { .. }),
            "{err}"
        );
        // Garbage over the payload, the header intact.
        let mut bytes = encode(Kind::Cloth, &sample());
        for b in &mut bytes[HEADER + 3..HEADER + 20] {
            *b = b'#';
        }
        let err = decode(path, &bytes).unwrap_err();
        assert!(matches!(err, CheckpointError::Checksum { .. }), "{err}");
        assert!(err.to_string().contains("corrupted"));
        let mut bytes = encode(Kind::Cloth, &sample());
        bytes.extend_from_slice(b"tail");
        let err = decode(path, &bytes).unwrap_err();
        assert!(err.to_string().contains("appended"), "{err}");
    }

    #[test]
    fn wrong_version_and_kind_are_refused() {
        let path = Path::new("checkpoint.symlab");
        // A well-formed file of another version: rebuild its checksum.
        let mut bytes = encode(Kind::Cloth, &sample());
        bytes[8..12].copy_from_slice(&(FORMAT_VERSION + 1).to_le_bytes());
        let mut crc = crc32fast::Hasher::new();
        crc.update(&bytes[..24]);
        crc.update(&bytes[HEADER..]);
        let sum = crc.finalize().to_le_bytes();
        bytes[24..28].copy_from_slice(&sum);
        let err = decode(path, &bytes).unwrap_err();
        assert!(matches!(err, CheckpointError::Version { .. }), "{err}");
        let text = err.to_string();
        assert!(
            text.contains(&format!("version {}", FORMAT_VERSION + 1))
                && text.contains(&format!("reads version {FORMAT_VERSION} only")),
            "{err}"
        );

        let dir = temp_dir("kind");
        let p = dir.join(FILE_NAME);
        write(&p, Kind::Compare, &sample()).unwrap();
        let err = read(&p, Kind::Cloth).unwrap_err();
        assert!(
            err.to_string().contains("kind compare, expected cloth"),
            "{err}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn decoder_refuses_short_and_oversized_fields() {
        let path = Path::new("p");
        let mut e = Encoder::new();
        e.usize(usize::MAX / 2);
        let b = e.finish();
        let err = Decoder::new(path, &b).f64s("state").unwrap_err();
        assert!(err.to_string().contains("state"), "{err}");
        let mut e = Encoder::new();
        e.f64(1.0).u64(3);
        let b = e.finish();
        let mut d = Decoder::new(path, &b);
        d.f64("x").unwrap();
        assert!(d.end().is_err());
        let mut out = [0.0; 2];
        let mut e = Encoder::new();
        e.f64s(&[1.0, 2.0, 3.0]);
        let b = e.finish();
        let err = Decoder::new(path, &b).f64s_into(&mut out, "q").unwrap_err();
        assert!(
            err.to_string().contains("3 values, this run has 2"),
            "{err}"
        );
    }

    #[test]
    fn unwritable_directory_is_an_error_naming_the_path() {
        let err = write(
            Path::new("/nonexistent-dir-symlab/checkpoint.symlab"),
            Kind::Cloth,
            b"x",
        )
        .unwrap_err();
        assert!(
            err.to_string().starts_with("/nonexistent-dir-symlab/"),
            "{err}"
        );
    }
}
