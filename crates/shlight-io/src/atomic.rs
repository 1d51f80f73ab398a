//! Writing a file all at once or not at all.
//!
//! The contents go to a temporary file in the destination's directory,
//! named `.NAME.tmp-PID-N`, which is flushed to disk and then renamed over
//! the destination (on Linux the kernel is asked to start writing it back
//! after every MiB, so the flush waits for the tail only). A rename within one directory is atomic, so a reader
//! sees either the old file or the complete new one, and a failed write
//! leaves the old file untouched and no temporary file behind.

use std::ffi::OsString;
use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::{IoError, IoErrorKind};

/// Writes the file at `path` through `write`, atomically: the destination
/// is replaced only when `write` returns `Ok` and everything reached the
/// disk; on any error (or a panic in `write`) the temporary file is removed
/// and an existing file at `path` is left as it was.
///
/// `write` receives a buffered writer; it need not flush. The new file gets
/// default permissions, and a symbolic link at `path` is replaced rather than
/// written through. Used by [`crate::write_image`], and meant for any output
/// file (JSON, text).
///
/// # Errors
/// [`IoErrorKind::Write`] with the first I/O error: from creating the
/// temporary file, from `write`, from flushing, or from the rename (for
/// example when `path` is a directory).
///
/// # Example
/// ```
/// # let dir = std::env::temp_dir();
/// let path = dir.join(format!("shlight-io-doctest-{}.txt", std::process::id()));
/// shlight_io::write_atomically(&path, |w| writeln!(w, "hello"))?;
/// assert_eq!(std::fs::read_to_string(&path).unwrap(), "hello\n");
/// # std::fs::remove_file(&path).unwrap();
/// # Ok::<(), shlight_io::IoError>(())
/// ```
pub fn write_atomically<F>(path: &Path, write: F) -> Result<(), IoError>
where
    F: FnOnce(&mut dyn Write) -> io::Result<()>,
{
    write_file_atomically(path, |w| write(w).map_err(IoErrorKind::Write))
}

/// [`write_atomically`] with a concrete, seekable writer (some encoders
/// need `Seek`) and an [`IoErrorKind`] from the closure.
pub(crate) fn write_file_atomically<F>(path: &Path, write: F) -> Result<(), IoError>
where
    F: FnOnce(&mut BufWriter<Writeback>) -> Result<(), IoErrorKind>,
{
    let error = |kind| IoError::new(path, kind);
    let io_error = |e| error(IoErrorKind::Write(e));

    let file_name = path.file_name().ok_or_else(|| {
        io_error(io::Error::new(
            io::ErrorKind::InvalidInput,
            "the path does not name a file",
        ))
    })?;
    let dir = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let (temp, file) = TempFile::create(dir.join(temp_name(file_name))).map_err(io_error)?;

    let mut writer = BufWriter::new(Writeback { file, unsynced: 0 });
    write(&mut writer).map_err(error)?;
    let file = writer
        .into_inner()
        .map_err(|e| io_error(e.into_error()))?
        .file;
    file.sync_all().map_err(io_error)?;
    // Closed before the rename, which some systems require.
    drop(file);
    temp.persist(path).map_err(io_error)
}

/// `.NAME.tmp-PID-N`, unique within this process by the counter.
fn temp_name(file_name: &std::ffi::OsStr) -> OsString {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let mut name = OsString::from(".");
    name.push(file_name);
    name.push(format!(".tmp-{}-{n}", std::process::id()));
    name
}

/// A temporary file's path; the file is removed when this is dropped unless
/// persisted.
struct TempFile {
    path: PathBuf,
    persisted: bool,
}

impl TempFile {
    /// Creates the file (failing if it exists) and opens it for writing.
    fn create(path: PathBuf) -> io::Result<(Self, File)> {
        let file = OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&path)?;
        let temp = Self {
            path,
            persisted: false,
        };
        Ok((temp, file))
    }

    /// Renames the file to `destination`, replacing what is there.
    fn persist(mut self, destination: &Path) -> io::Result<()> {
        fs::rename(&self.path, destination)?;
        self.persisted = true;
        Ok(())
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if !self.persisted {
            // Nothing more can be done if this fails; the error that got us
            // here is the one worth reporting.
            let _ = fs::remove_file(&self.path);
        }
    }
}

/// The temporary file, asking the kernel to start writing its dirty pages
/// to disk after every [`WRITEBACK_EVERY`] bytes (Linux's
/// `sync_file_range(SYNC_FILE_RANGE_WRITE)`, which does not wait), so that
/// the disk works while the rest is formatted and the final `fsync` waits
/// only for the tail.
pub(crate) struct Writeback {
    file: File,
    unsynced: usize,
}

/// Bytes written between two starts of write-back.
const WRITEBACK_EVERY: usize = 1 << 20;

impl Write for Writeback {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.file.write(buf)?;
        self.unsynced += n;
        if self.unsynced >= WRITEBACK_EVERY {
            self.unsynced = 0;
            #[cfg(target_os = "linux")]
            {
                use std::os::fd::AsRawFd;
                // SAFETY: a plain system call on an open descriptor; its
                // failure only means no early write-back.
                unsafe {
                    libc::sync_file_range(self.file.as_raw_fd(), 0, 0, libc::SYNC_FILE_RANGE_WRITE);
                }
            }
        }
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.file.flush()
    }
}

impl std::io::Seek for Writeback {
    fn seek(&mut self, pos: std::io::SeekFrom) -> io::Result<u64> {
        self.file.seek(pos)
    }
}
