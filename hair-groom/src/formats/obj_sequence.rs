//! Numbered OBJ sequences of one deforming mesh (`body.####.obj`): one file per frame, each
//! read by [`super::obj::load_obj`] (meters, Z up, the same [`ObjOptions`]).
//!
//! The pattern's file name holds one run of `#`: the frame number, zero-padded to the run's
//! width (`body.####.obj` frame 7 is `body.0007.obj`; a number wider than the run is written in
//! full, `body.12345.obj`, as Blender and Houdini name frames). Every frame must have the rest
//! frame's topology — vertex count and triangles — because hair roots are samples of its
//! triangles: a frame with another topology, and a missing frame, are errors that name the file
//! and the frame (a missing frame's error lists the frames the directory has).

use std::path::{Path, PathBuf};

use hair_core::TriMesh;
use nalgebra::Vector3;

use super::bad;
use super::obj::{load_obj, ObjOptions};
use crate::error::{FileLocation, GroomError};

/// Largest number of frames listed by scanning a sequence's directory (for the message of a
/// missing frame): a bound on the work an error message does.
const MAX_LISTED: usize = 100_000;

/// A numbered OBJ sequence (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct ObjSequence {
    /// The pattern as given (`dir/body.####.obj`).
    pattern: PathBuf,
    /// File name before and after the `#` run.
    prefix: String,
    suffix: String,
    /// Width of the `#` run.
    digits: usize,
    /// Unit scale and up axis of every frame.
    opts: ObjOptions,
}

impl ObjSequence {
    /// A sequence of files named by `pattern`, whose file name holds exactly one run of `#`;
    /// refuses another pattern, naming it and the fix.
    pub fn new(pattern: &Path, opts: ObjOptions) -> Result<Self, GroomError> {
        let name = pattern
            .file_name()
            .and_then(|n| n.to_str())
            .ok_or_else(|| {
                bad(
                    pattern,
                    FileLocation::File,
                    "names no file (or is not UTF-8); give a pattern like body.####.obj",
                )
            })?;
        let start = name.find('#');
        let runs = name
            .as_bytes()
            .windows(2)
            .filter(|w| w[0] != b'#' && w[1] == b'#')
            .count()
            + usize::from(name.starts_with('#'));
        let Some(start) = start.filter(|_| runs == 1) else {
            return Err(bad(
                pattern,
                FileLocation::File,
                format!(
                    "is not a frame pattern: its file name needs exactly one run of `#` for the \
                     zero-padded frame number (it has {runs}), e.g. body.####.obj"
                ),
            ));
        };
        let digits = name[start..].bytes().take_while(|&b| b == b'#').count();
        Ok(Self {
            pattern: pattern.to_path_buf(),
            prefix: name[..start].to_string(),
            suffix: name[start + digits..].to_string(),
            digits,
            opts,
        })
    }

    /// The pattern as given.
    pub fn pattern(&self) -> &Path {
        &self.pattern
    }

    /// The file of `frame`: the `#` run replaced by the frame number, zero-padded.
    pub fn frame_path(&self, frame: u32) -> PathBuf {
        let name = format!(
            "{}{:0width$}{}",
            self.prefix,
            frame,
            self.suffix,
            width = self.digits
        );
        self.pattern.with_file_name(name)
    }

    /// The mesh of `frame` (meters, Z up). A missing file is an error naming the file, the
    /// frame and the frames the directory has.
    pub fn mesh_at(&self, frame: u32) -> Result<TriMesh, GroomError> {
        let path = self.frame_path(frame);
        if !path.exists() {
            return Err(bad(
                &path,
                FileLocation::File,
                format!(
                    "frame {frame} of the sequence {} is missing; {}",
                    self.pattern.display(),
                    self.describe_frames()
                ),
            ));
        }
        load_obj(&path, &self.opts).map_err(|e| {
            bad(
                &path,
                FileLocation::File,
                format!(
                    "frame {frame} of the sequence {}: {e}",
                    self.pattern.display()
                ),
            )
        })
    }

    /// Vertex positions of `frame` (m, Z up), in the order of `rest`, the sequence's rest
    /// frame `rest_frame`. Refuses a frame whose vertex count or triangles differ from
    /// `rest`'s, naming the file and both frames.
    pub fn positions_at(
        &self,
        frame: u32,
        rest: &TriMesh,
        rest_frame: u32,
    ) -> Result<Vec<Vector3<f32>>, GroomError> {
        let mesh = self.mesh_at(frame)?;
        if mesh.positions().len() != rest.positions().len() || mesh.triangles() != rest.triangles()
        {
            return Err(bad(
                &self.frame_path(frame),
                FileLocation::File,
                format!(
                    "frame {frame}: the topology changes: {} vertices and {} triangles, but frame \
                     {rest_frame} ({}) has {} and {} (or other faces); every frame of a sequence \
                     needs the same vertices and faces (export the deformation, not a remesh)",
                    mesh.positions().len(),
                    mesh.triangles().len(),
                    self.frame_path(rest_frame).display(),
                    rest.positions().len(),
                    rest.triangles().len()
                ),
            ));
        }
        Ok(mesh.positions().to_vec())
    }

    /// The frames present in the pattern's directory, as "the directory has frames 1–6, 8–24"
    /// (or that it has none).
    fn describe_frames(&self) -> String {
        let dir = match self.pattern.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let Ok(entries) = std::fs::read_dir(&dir) else {
            return format!("its directory {} cannot be read", dir.display());
        };
        let mut frames: Vec<u32> = entries
            .take(MAX_LISTED)
            .filter_map(|e| e.ok()?.file_name().into_string().ok())
            .filter_map(|n| {
                let digits = n.strip_prefix(&self.prefix)?.strip_suffix(&self.suffix)?;
                let ok = digits.len() >= self.digits && digits.bytes().all(|b| b.is_ascii_digit());
                ok.then(|| digits.parse().ok()).flatten()
            })
            .collect();
        frames.sort_unstable();
        if frames.is_empty() {
            return format!(
                "{} has no file of this sequence; check the pattern (relative to the scene file)",
                dir.display()
            );
        }
        let mut runs: Vec<String> = Vec::new();
        let mut i = 0;
        while i < frames.len() && runs.len() < 10 {
            let mut j = i;
            while j + 1 < frames.len() && frames[j + 1] == frames[j] + 1 {
                j += 1;
            }
            runs.push(if i == j {
                frames[i].to_string()
            } else {
                format!("{}–{}", frames[i], frames[j])
            });
            i = j + 1;
        }
        let more = if i < frames.len() { ", …" } else { "" };
        format!(
            "the directory has frames {}{more}; export every frame of the scene's range",
            runs.join(", ")
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write_quad(dir: &Path, name: &str, z: f32, faces: &str) {
        std::fs::write(
            dir.join(name),
            format!("v 0 0 {z}\nv 1 0 {z}\nv 1 1 {z}\nv 0 1 {z}\n{faces}"),
        )
        .unwrap();
    }

    #[test]
    fn frames_are_zero_padded_to_the_run() {
        let s = ObjSequence::new(Path::new("a/body.####.obj"), ObjOptions::default()).unwrap();
        assert_eq!(s.frame_path(7), Path::new("a/body.0007.obj"));
        assert_eq!(s.frame_path(12345), Path::new("a/body.12345.obj"));
        for bad in ["body.obj", "b#dy.##.obj"] {
            let e = ObjSequence::new(Path::new(bad), ObjOptions::default()).unwrap_err();
            assert!(e.to_string().contains("exactly one run of `#`"), "{e}");
        }
    }

    #[test]
    fn missing_frame_names_the_file_and_the_frames_present() {
        let dir = tempfile::tempdir().unwrap();
        for f in [1, 2, 3, 5] {
            write_quad(dir.path(), &format!("b.{f:03}.obj"), 0.0, "f 1 2 3 4\n");
        }
        let s = ObjSequence::new(&dir.path().join("b.###.obj"), ObjOptions::default()).unwrap();
        let rest = s.mesh_at(1).unwrap();
        assert!(s.positions_at(5, &rest, 1).is_ok());
        let e = s.positions_at(4, &rest, 1).unwrap_err().to_string();
        assert!(
            e.contains("b.004.obj") && e.contains("frame 4") && e.contains("1–3, 5"),
            "{e}"
        );
    }

    #[test]
    fn a_frame_with_other_faces_is_a_topology_change() {
        let dir = tempfile::tempdir().unwrap();
        write_quad(dir.path(), "b.1.obj", 0.0, "f 1 2 3 4\n");
        write_quad(dir.path(), "b.2.obj", 0.1, "f 1 2 3 4\n");
        write_quad(dir.path(), "b.3.obj", 0.2, "f 1 2 4\nf 2 3 4\n");
        let s = ObjSequence::new(&dir.path().join("b.#.obj"), ObjOptions::default()).unwrap();
        let rest = s.mesh_at(1).unwrap();
        let moved = s.positions_at(2, &rest, 1).unwrap();
        assert_eq!(moved[0], Vector3::new(0.0, 0.0, 0.1));
        let e = s.positions_at(3, &rest, 1).unwrap_err().to_string();
        assert!(
            e.contains("b.3.obj") && e.contains("frame 3") && e.contains("topology changes"),
            "{e}"
        );
    }
}
