//! Opening input files safely: only regular files, read whole under a size cap.
//!
//! A path may name something that is not a file: a directory, a FIFO (opening it blocks until a
//! writer appears), a device such as `/dev/zero` (reading it never ends). [`check_regular_file`]
//! refuses those by name from the path's metadata, before anything is opened, and
//! [`read_regular_file`] then reads a file whole only if it is within a size limit, so a huge or
//! growing file is refused with its size rather than read until memory runs out. Every reader of
//! this crate goes through them; other crates reading user files (scene files, meshes) can too.

use std::fs::{File, FileType};
use std::io::Read;
use std::path::{Path, PathBuf};

use thiserror::Error;

/// Largest groom or mesh file read, bytes (2 GiB): far above real grooms (the Sintel groom's
/// `.tfx` is 114 KiB; ten million points of `.hair` are 120 MB).
pub const MAX_GROOM_FILE_BYTES: u64 = 2 << 30;

/// Why an input file was refused.
#[derive(Debug, Error)]
pub enum InputFileError {
    /// The path names a directory, FIFO, socket or device, not a regular file.
    #[error("`{}` is a {kind}, not a regular file; give the path of a file", .path.display())]
    NotAFile {
        /// The path given.
        path: PathBuf,
        /// What it is: "directory", "FIFO (named pipe)", "device", "socket" or "special file".
        kind: &'static str,
    },
    /// The file is larger than the reader's limit.
    #[error(
        "`{}` is {bytes} bytes, more than the {limit} bytes read from one such file; check that \
         it is the right file, or split it into smaller files",
        .path.display()
    )]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Its size (or, if it grew while being read, the bytes read), bytes.
        bytes: u64,
        /// The limit, bytes.
        limit: u64,
    },
    /// The operating system refused to open or read the file.
    #[error(
        "cannot read `{}`: {source}; check that the path is right and the file is readable",
        .path.display()
    )]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
}

/// Checks that `path` names a regular file (following symbolic links) without opening it, and
/// returns its size in bytes; a directory, FIFO, socket or device is refused by name.
pub fn check_regular_file(path: &Path) -> Result<u64, InputFileError> {
    let meta = std::fs::metadata(path).map_err(|source| io(path, source))?;
    regular(path, meta.file_type())?;
    Ok(meta.len())
}

/// Opens the regular file at `path` ([`check_regular_file`] first, then the open file is checked
/// again in case the path changed in between) and returns it with its size in bytes.
pub fn open_regular_file(path: &Path) -> Result<(File, u64), InputFileError> {
    check_regular_file(path)?;
    let file = File::open(path).map_err(|source| io(path, source))?;
    let meta = file.metadata().map_err(|source| io(path, source))?;
    regular(path, meta.file_type())?;
    Ok((file, meta.len()))
}

/// Reads the whole regular file at `path` if it holds at most `limit` bytes; a larger file (or
/// one that grows past `limit` while it is read) is refused with its size.
pub fn read_regular_file(path: &Path, limit: u64) -> Result<Vec<u8>, InputFileError> {
    let (file, len) = open_regular_file(path)?;
    let too_large = |bytes| InputFileError::TooLarge {
        path: path.to_path_buf(),
        bytes,
        limit,
    };
    if len > limit {
        return Err(too_large(len));
    }
    let mut bytes = Vec::with_capacity(len as usize);
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|source| io(path, source))?;
    if bytes.len() as u64 > limit {
        return Err(too_large(bytes.len() as u64));
    }
    Ok(bytes)
}

fn io(path: &Path, source: std::io::Error) -> InputFileError {
    InputFileError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// `Ok` for a regular file, else [`InputFileError::NotAFile`] naming what it is.
fn regular(path: &Path, file_type: FileType) -> Result<(), InputFileError> {
    #[cfg(unix)]
    use std::os::unix::fs::FileTypeExt;
    let kind = match file_type {
        t if t.is_file() => return Ok(()),
        t if t.is_dir() => "directory",
        #[cfg(unix)]
        t if t.is_fifo() => "FIFO (named pipe)",
        #[cfg(unix)]
        t if t.is_char_device() || t.is_block_device() => "device",
        #[cfg(unix)]
        t if t.is_socket() => "socket",
        _ => "special file",
    };
    Err(InputFileError::NotAFile {
        path: path.to_path_buf(),
        kind,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regular_files_are_read_within_the_limit() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.txt");
        std::fs::write(&path, b"hello").unwrap();
        assert_eq!(check_regular_file(&path).unwrap(), 5);
        assert_eq!(read_regular_file(&path, 5).unwrap(), b"hello");
        let err = read_regular_file(&path, 4).unwrap_err().to_string();
        assert!(err.contains("a.txt") && err.contains("5 bytes") && err.contains("4 bytes"));
    }

    #[test]
    fn directories_and_devices_are_refused_by_name() {
        let dir = tempfile::tempdir().unwrap();
        let err = read_regular_file(dir.path(), 10).unwrap_err().to_string();
        assert!(err.contains("is a directory"), "{err}");
        #[cfg(unix)]
        {
            let err = read_regular_file(Path::new("/dev/zero"), 10)
                .unwrap_err()
                .to_string();
            assert!(err.contains("`/dev/zero` is a device"), "{err}");
        }
        let err = check_regular_file(&dir.path().join("missing"))
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("cannot read") && err.contains("missing"),
            "{err}"
        );
    }
}
