//! Opening a cache for reading: only regular files. A device such as `/dev/zero` never ends and a
//! FIFO blocks until someone writes to it, so both are refused by name before a byte is read.
//! (`hair-groom` has the same check for groom and mesh files; this crate does not depend on it.)

use std::fs::File;
use std::path::Path;

use crate::error::CacheError;

/// Opens the regular file at `path` and returns it with its length, bytes. Anything else (a
/// directory, a FIFO, a socket, a device) is a [`CacheError::NotAFile`] naming what it is.
pub(crate) fn open_regular(path: &Path) -> Result<(File, u64), CacheError> {
    let io = |action, source| CacheError::Io {
        path: path.to_path_buf(),
        action,
        source,
    };
    // `metadata` follows symbolic links and does not open the file, so a FIFO cannot block here.
    let kind = std::fs::metadata(path)
        .map_err(|e| io("open", e))?
        .file_type();
    if !kind.is_file() {
        return Err(not_a_file(path, &kind));
    }
    let file = File::open(path).map_err(|e| io("open", e))?;
    // Checked again on the open file, in case the path was replaced in between.
    let meta = file.metadata().map_err(|e| io("read the size of", e))?;
    if !meta.file_type().is_file() {
        return Err(not_a_file(path, &meta.file_type()));
    }
    Ok((file, meta.len()))
}

fn not_a_file(path: &Path, kind: &std::fs::FileType) -> CacheError {
    #[cfg(unix)]
    use std::os::unix::fs::FileTypeExt;
    let kind = match kind {
        k if k.is_dir() => "directory",
        #[cfg(unix)]
        k if k.is_fifo() => "FIFO (named pipe)",
        #[cfg(unix)]
        k if k.is_char_device() || k.is_block_device() => "device",
        #[cfg(unix)]
        k if k.is_socket() => "socket",
        _ => "special file",
    };
    CacheError::NotAFile {
        path: path.to_path_buf(),
        kind,
    }
}
