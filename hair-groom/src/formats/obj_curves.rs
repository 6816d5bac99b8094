//! Guide curves as Wavefront OBJ polylines, read and written: `v x y z` vertices and one `l`
//! element per curve (`l 1 2 3 …`, 1-based indices, negative ones relative to the last vertex,
//! `v/vt` pairs accepted and the texture index ignored). Every other element (faces, normals,
//! groups, materials) is ignored, so a scene exported with both a mesh and curves reads its
//! curves only. Line continuations (`\`) are not supported.
//!
//! Errors name the file and the 1-based line. The writer writes every vertex with the shortest
//! decimal that reads back to the same f32, so write → read is bit-exact.

use std::fmt::Write as _;
use std::path::Path;

use nalgebra::Vector3;

use super::{bad, check_options, read_bytes, to_file, to_world, write_bytes, ImportOptions};
use crate::error::{FileLocation, GroomError};
use crate::groom::Groom;

/// Reads the OBJ file at `path`: one curve per `l` element, in meters, Z up (`opts`: the file's
/// unit scale and up axis). A file without `l` elements is refused.
pub fn read_obj_curves(path: &Path, opts: &ImportOptions) -> Result<Groom, GroomError> {
    check_options(opts)?;
    let bytes = read_bytes(path)?;
    let text = String::from_utf8(bytes).map_err(|e| {
        bad(
            path,
            FileLocation::Byte(e.utf8_error().valid_up_to() as u64),
            "is not UTF-8 text: an OBJ file is text (this looks like a binary file)",
        )
    })?;
    parse(&text, path, opts)
}

/// Writes `groom` to `path` as OBJ vertices and one `l` polyline per curve, in file units and up
/// axis per `opts`.
pub fn write_obj_curves(
    path: &Path,
    groom: &Groom,
    opts: &ImportOptions,
) -> Result<(), GroomError> {
    check_options(opts)?;
    write_bytes(path, encode(groom, opts).as_bytes())
}

/// Parses OBJ text; `path` names it in errors.
fn parse(text: &str, path: &Path, opts: &ImportOptions) -> Result<Groom, GroomError> {
    let mut vertices: Vec<Vector3<f32>> = Vec::new();
    // Each curve as (line, 0-based vertex indices), resolved once every vertex is known.
    let mut lines: Vec<(usize, Vec<i64>)> = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let at = FileLocation::Line(n + 1);
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let mut c = [0.0f32; 3];
                for x in &mut c {
                    let word = words
                        .next()
                        .ok_or_else(|| bad(path, at, "`v` needs three coordinates `v x y z`"))?;
                    *x = word.parse().map_err(|_| {
                        bad(path, at, format!("`{word}` is not a number in a `v` line"))
                    })?;
                }
                if !c.iter().all(|x| x.is_finite()) {
                    return Err(bad(
                        path,
                        at,
                        format!(
                            "vertex {} has a non-finite coordinate {c:?}",
                            vertices.len() + 1
                        ),
                    ));
                }
                vertices.push(to_world(c, opts));
            }
            Some("l") => {
                let mut indices = Vec::new();
                for word in words {
                    let first = word.split('/').next().unwrap_or(word);
                    let i: i64 = first.parse().map_err(|_| {
                        bad(
                            path,
                            at,
                            format!("`{word}` is not a vertex index in an `l` line"),
                        )
                    })?;
                    let resolved = match i {
                        0 => return Err(bad(path, at, "vertex index 0: OBJ indices start at 1")),
                        i if i > 0 => i - 1,
                        i => vertices.len() as i64 + i,
                    };
                    indices.push(resolved);
                }
                if indices.len() < 2 {
                    return Err(bad(
                        path,
                        at,
                        format!(
                            "`l` has {} vertex index(es); a curve needs at least 2",
                            indices.len()
                        ),
                    ));
                }
                lines.push((n + 1, indices));
            }
            _ => {}
        }
    }
    if lines.is_empty() {
        return Err(bad(
            path,
            FileLocation::File,
            "has no `l` polylines: export the hair as curves/lines (Blender: convert the curves \
             to a mesh of edges, then File > Export > Wavefront with edges)",
        ));
    }
    let mut curves = Vec::with_capacity(lines.len());
    for (line, indices) in lines {
        let curve = indices
            .iter()
            .map(|&i| {
                usize::try_from(i)
                    .ok()
                    .and_then(|i| vertices.get(i).copied())
                    .ok_or_else(|| {
                        bad(
                            path,
                            FileLocation::Line(line),
                            format!(
                                "vertex index {} is out of range: the file has {} vertices",
                                i + 1,
                                vertices.len()
                            ),
                        )
                    })
            })
            .collect::<Result<Vec<_>, _>>()?;
        curves.push(curve);
    }
    Groom::new(curves)
}

/// The OBJ text of `groom`.
fn encode(groom: &Groom, opts: &ImportOptions) -> String {
    let mut out = String::from("# guide curves written by hairsys\n");
    for p in groom.curves().iter().flatten() {
        let [x, y, z] = to_file(p, opts);
        // `{:?}` prints the shortest decimal that parses back to the same f32.
        let _ = writeln!(out, "v {x:?} {y:?} {z:?}");
    }
    let mut next = 1usize;
    for curve in groom.curves() {
        out.push('l');
        for i in next..next + curve.len() {
            let _ = write!(out, " {i}");
        }
        out.push('\n');
        next += curve.len();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::obj::UpAxis;
    use crate::formats::test_support::{assert_round_trip, tricky_groom};

    fn parse_err(text: &str) -> String {
        parse(text, Path::new("c.obj"), &ImportOptions::default())
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn write_then_read_is_bit_exact() {
        assert_round_trip(&tricky_groom(), |g, opts| {
            let text = encode(g, opts);
            parse(&text, Path::new("m.obj"), opts).unwrap_or_else(|e| panic!("{e}\n{text}"))
        });
    }

    #[test]
    fn polylines_with_relative_and_textured_indices() {
        let text = "# two curves and a face\nv 0 0 0\nv 0 0 1\nv 0 0 2\nvt 0 0\nf 1 2 3\nl 1/1 2/1 3/1\nv 1 0 0\nv 1 0 1\nl -2 -1\n";
        let opts = ImportOptions {
            scale: 0.5,
            up_axis: UpAxis::Y,
        };
        let g = parse(text, Path::new("c.obj"), &opts).unwrap();
        assert_eq!(g.len(), 2);
        // Y up: file (0, 0, 2) → (0, −2, 0) · 0.5.
        assert_eq!(g.curves()[0][2], Vector3::new(0.0, -1.0, 0.0));
        assert_eq!(g.curves()[1][1], Vector3::new(0.5, -0.5, 0.0));
    }

    #[test]
    fn bad_lines_are_named() {
        assert!(parse_err("v 0 0 0\nv 1 banana 0\n").contains("c.obj line 2"));
        assert!(parse_err("v 0 0\n").contains("three coordinates"));
        assert!(
            parse_err("v 0 0 nan\nv 0 0 1\nl 1 2\n").contains("line 1: vertex 1 has a non-finite")
        );
        assert!(parse_err("v 0 0 0\nl 1\n").contains("line 2"));
        assert!(parse_err("v 0 0 0\nv 1 1 1\nl 1 0\n").contains("start at 1"));
        let msg = parse_err("v 0 0 0\nv 1 1 1\nl 1 7\n");
        assert!(
            msg.contains("line 3") && msg.contains("index 7 is out of range"),
            "{msg}"
        );
        assert!(parse_err("v 0 0 0\nl -5 1\n").contains("out of range"));
        assert!(parse_err("v 0 0 0\nf 1 1 1\n").contains("no `l` polylines"));
    }

    #[test]
    fn every_truncation_and_corruption_is_handled() {
        let g = Groom::new(vec![vec![Vector3::zeros(), Vector3::x(), Vector3::y()]]).unwrap();
        let text = encode(&g, &ImportOptions::default());
        for n in 0..text.len() {
            let _ = parse(&text[..n], Path::new("t.obj"), &ImportOptions::default());
        }
        for i in 0..text.len() {
            for c in ["l", "v", "-", "0", "/", " ", "\n"] {
                let bad = format!("{}{c}{}", &text[..i], &text[i + 1..]);
                let _ = parse(&bad, Path::new("t.obj"), &ImportOptions::default());
            }
        }
    }
}
