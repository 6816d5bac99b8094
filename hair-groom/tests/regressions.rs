//! Paths that hung or exhausted memory in every reader: a groom or OBJ mesh at
//! `/dev/zero` was read until memory ran out (the OBJ mesh reader aborted), a FIFO blocked the
//! reader forever, and a directory gave an operating-system error without saying what was wrong.
//! Each reader must now refuse them by name before reading, and refuse a file above its size
//! limit with the size and the limit.
//!
//! Inputs the fuzzer (`tests/fuzz.rs`) found crashing a reader are kept under
//! `tests/regressions/`, each test named after the failure.

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

use hair_groom::input_file::MAX_GROOM_FILE_BYTES;
use hair_groom::{
    load_obj, read_groom, read_hair, read_obj_curves, read_tfx, read_usda, GroomError,
    ImportOptions, ObjOptions,
};

/// A reader of one format, by name.
type Reader = (&'static str, fn(&Path) -> Result<(), GroomError>);

/// Every file reader of the crate.
const READERS: [Reader; 6] = [
    (".hair", |p| {
        read_hair(p, &ImportOptions::default()).map(drop)
    }),
    (".tfx", |p| read_tfx(p, &ImportOptions::default()).map(drop)),
    ("OBJ curves", |p| {
        read_obj_curves(p, &ImportOptions::default()).map(drop)
    }),
    (".usda", |p| {
        read_usda(p, &ImportOptions::default()).map(drop)
    }),
    ("groom by extension", |p| {
        read_groom(p, &ImportOptions::default()).map(drop)
    }),
    ("OBJ mesh", |p| {
        load_obj(p, &ObjOptions::default()).map(drop)
    }),
];

/// Runs every reader on `path` in a thread (so a reader that blocks fails the test instead of
/// hanging it) and checks that each error names the path and contains `expected`.
fn every_reader_refuses(path: &Path, expected: &str) {
    for (name, read) in READERS {
        let (send, receive) = mpsc::channel();
        let p = path.to_path_buf();
        std::thread::spawn(move || {
            let _ = send.send(read(&p).map_err(|e| e.to_string()));
        });
        let result = receive
            .recv_timeout(Duration::from_secs(10))
            .unwrap_or_else(|_| panic!("the {name} reader blocked on {}", path.display()));
        let err = result.expect_err(name);
        assert!(
            err.contains(&path.display().to_string()) && err.contains(expected),
            "{name}: {err}"
        );
    }
}

/// `dir/name` as a symbolic link to `target`, so the readers that pick a format by extension see
/// one.
fn link(dir: &Path, name: &str, target: &Path) -> PathBuf {
    let link = dir.join(name);
    std::os::unix::fs::symlink(target, &link).unwrap();
    link
}

#[test]
fn dev_zero_is_refused_not_read_until_memory_runs_out() {
    every_reader_refuses(Path::new("/dev/zero"), "is a device, not a regular file");
    let dir = tempfile::tempdir().unwrap();
    for ext in ["hair", "obj", "usda"] {
        let zero = link(dir.path(), &format!("zero.{ext}"), Path::new("/dev/zero"));
        every_reader_refuses(&zero, "is a device");
    }
}

#[test]
fn fifo_is_refused_not_waited_on() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["pipe.hair", "pipe.tfx", "pipe.obj", "pipe.usda"] {
        let fifo = dir.path().join(name);
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        assert!(made.is_ok_and(|s| s.success()), "mkfifo failed");
        every_reader_refuses(&fifo, "is a FIFO (named pipe), not a regular file");
    }
}

#[test]
fn directory_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    every_reader_refuses(dir.path(), "is a directory, not a regular file");
    let named = dir.path().join("groom.hair");
    std::fs::create_dir(&named).unwrap();
    every_reader_refuses(&named, "is a directory");
}

#[test]
fn file_above_the_size_limit_is_refused_with_its_size() {
    let dir = tempfile::tempdir().unwrap();
    // Sparse: takes no disk space, and must not be read.
    let bytes = MAX_GROOM_FILE_BYTES + 1;
    for ext in ["hair", "tfx", "obj", "usda"] {
        let path = dir.path().join(format!("huge.{ext}"));
        std::fs::File::create(&path)
            .unwrap()
            .set_len(bytes)
            .unwrap();
        every_reader_refuses(
            &path,
            &format!("is {bytes} bytes, more than the {MAX_GROOM_FILE_BYTES} bytes"),
        );
    }
}

/// Found by `tests/fuzz.rs` (OBJ mesh reader, long run): a face `4/4/-2147483648` made tobj
/// 4.0.5 compute `vn * 3` on the wrapped relative index and panic ("attempt to multiply with
/// overflow"; in a release build the product wraps and indexes arbitrary normals). Face indices
/// are now checked against the elements defined above them before tobj resolves them.
#[test]
fn face_normal_index_overflow() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/regressions/face_normal_index_overflow.obj");
    let err = load_obj(&path, &ObjOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("face_normal_index_overflow.obj")
            && err.contains("line 15: face index `-2147483648` refers to no normal"),
        "{err}"
    );
}
