//! Foxglove's official Python reader (`pip install mcap`) reads every cache the writer makes.
//! Needs `python3` with the `mcap` package; fails (never skips) without them.

mod common;

use std::path::Path;
use std::process::Command;

use common::{frame_data, header, layout};
use hair_cache::{CacheWriter, Compression, Precision, WriterOptions};

const SCRIPT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tests/python/read_with_mcap.py"
);

fn check_python() {
    let out = Command::new("python3")
        .args(["-c", "import mcap.reader"])
        .output();
    match out {
        Ok(out) if out.status.success() => {}
        Ok(out) => panic!(
            "python3 cannot import the `mcap` package ({}); run `pip install mcap`",
            String::from_utf8_lossy(&out.stderr).trim()
        ),
        Err(e) => panic!("cannot run python3 ({e}); install Python 3 and run `pip install mcap`"),
    }
}

/// Runs the script on `path`, asserts it accepts the file and returns its standard output.
fn read_with_python(path: &Path) -> String {
    let out = Command::new("python3")
        .arg(SCRIPT)
        .arg(path)
        .output()
        .expect("python3 runs");
    assert!(
        out.status.success(),
        "the Python mcap reader rejected {} (exit {:?}; `pip install mcap` if it is missing):\n{}{}",
        path.display(),
        out.status.code(),
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

#[test]
fn python_mcap_reads_every_compression_chunking_and_precision() {
    check_python();
    let dir = tempfile::tempdir().unwrap();
    let layout = layout();
    for precision in [Precision::F32, Precision::Quantized16] {
        for compression in [Compression::None, Compression::Lz4, Compression::Zstd] {
            for (chunk_size, frames) in
                [(WriterOptions::DEFAULT_CHUNK_SIZE, 30), (0, 5), (2000, 40)]
            {
                let path = dir.path().join(format!(
                    "{precision}-{compression}-{chunk_size}-{frames}.mcap"
                ));
                let options = WriterOptions {
                    compression,
                    chunk_size,
                    foxglove: None,
                    precision,
                };
                let mut writer = CacheWriter::create(&path, &header(), &layout, options).unwrap();
                for f in 1..=frames {
                    let (x, v) = frame_data(f, layout.point_count());
                    writer.write_frame(f, &x, &v).unwrap();
                }
                writer.finish().unwrap();
                let out = read_with_python(&path);
                assert_eq!(
                    out.contains("(quantized)"),
                    precision == Precision::Quantized16,
                    "{out}"
                );
            }
        }
    }
}

#[test]
fn python_mcap_reads_a_cache_without_frames() {
    check_python();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("empty.mcap");
    CacheWriter::create(&path, &header(), &layout(), WriterOptions::default())
        .unwrap()
        .finish()
        .unwrap();
    read_with_python(&path);
}
