//! USD `BasisCurves` in the `.usda` text format, read and written.
//!
//! The reader checks the `#usda` header, then takes every `def BasisCurves` prim of the file (at
//! any depth) and reads its default values of `curveVertexCounts` (`int[]`) and `points`
//! (`point3f[]`); the curves of all prims are concatenated in file order. Everything else is
//! skipped: other prims and attributes, time samples, the prims' transforms (`xformOp`s are not
//! applied), the stage's `upAxis` and `metersPerUnit` (the caller's [`ImportOptions`] decide) and
//! the curve `type`/`basis` (cubic curves are read as their control points). Binary `.usdc` and
//! `.usdz` are not read.
//!
//! Errors name the file and the 1-based line. The writer writes one linear `BasisCurves` prim
//! `/hair` with the stage's `upAxis` and `metersPerUnit` from `opts`, every coordinate as the
//! shortest decimal that reads back to the same f32, so write → read is bit-exact.

use std::fmt::Write as _;
use std::path::Path;

use nalgebra::Vector3;

use super::{bad, check_options, read_bytes, to_file, to_world, write_bytes, ImportOptions};
use crate::error::{FileLocation, GroomError};
use crate::formats::obj::UpAxis;
use crate::groom::Groom;

/// Reads the `.usda` file at `path`: the curves of every `BasisCurves` prim, in meters, Z up
/// (`opts`: the file's unit scale and up axis).
pub fn read_usda(path: &Path, opts: &ImportOptions) -> Result<Groom, GroomError> {
    check_options(opts)?;
    let bytes = read_bytes(path)?;
    let text = String::from_utf8(bytes).map_err(|e| {
        bad(
            path,
            FileLocation::Byte(e.utf8_error().valid_up_to() as u64),
            "is not UTF-8 text: only text .usda is read (convert .usdc/.usdz with `usdcat -o file.usda`)",
        )
    })?;
    parse(&text, path, opts)
}

/// Writes `groom` to `path` as one linear `BasisCurves` prim, in file units and up axis per
/// `opts` (also written as the stage's `metersPerUnit` and `upAxis`).
pub fn write_usda(path: &Path, groom: &Groom, opts: &ImportOptions) -> Result<(), GroomError> {
    check_options(opts)?;
    write_bytes(path, encode(groom, opts).as_bytes())
}

/// One token of `.usda` text.
#[derive(Debug, Clone, PartialEq)]
enum Tok<'a> {
    /// A name, keyword or number, as written.
    Word(&'a str),
    /// A quoted string, path `<…>` or asset `@…@`, without its delimiters.
    Str(&'a str),
    /// One punctuation character: `[ ] ( ) { } , = .` and the like.
    Punct(char),
}

/// Splits `text` into tokens with their 1-based lines, dropping `#` comments.
fn tokenize<'a>(text: &'a str, path: &Path) -> Result<Vec<(Tok<'a>, usize)>, GroomError> {
    let bytes = text.as_bytes();
    let mut toks = Vec::new();
    let (mut i, mut line) = (0usize, 1usize);
    while i < bytes.len() {
        let c = bytes[i];
        let start_line = line;
        match c {
            b'\n' => {
                line += 1;
                i += 1;
            }
            c if c.is_ascii_whitespace() => i += 1,
            b'#' => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
            }
            b'"' | b'\'' | b'<' | b'@' => {
                let close = match c {
                    b'<' => ">",
                    b'@' => "@",
                    b'"' if text[i..].starts_with("\"\"\"") => "\"\"\"",
                    b'\'' if text[i..].starts_with("'''") => "'''",
                    b'"' => "\"",
                    _ => "'",
                };
                let open_len = if close.len() == 3 { 3 } else { 1 };
                let body = i + open_len;
                let mut j = body;
                loop {
                    if j >= bytes.len() {
                        return Err(bad(
                            path,
                            FileLocation::Line(start_line),
                            "a string or path is not closed before the end of the file",
                        ));
                    }
                    if bytes[j] == b'\\' && close.len() == 1 && c != b'<' && c != b'@' {
                        j += 2;
                        continue;
                    }
                    if bytes[j..].starts_with(close.as_bytes()) {
                        break;
                    }
                    if bytes[j] == b'\n' {
                        line += 1;
                    }
                    j += 1;
                }
                toks.push((Tok::Str(&text[body..j]), start_line));
                i = j + close.len();
            }
            c if c.is_ascii_alphanumeric()
                || matches!(c, b'_' | b'-' | b'+')
                || (c == b'.' && bytes.get(i + 1).is_some_and(u8::is_ascii_digit)) =>
            {
                let start = i;
                let numeric = !(c.is_ascii_alphabetic() || c == b'_');
                while i < bytes.len() {
                    let d = bytes[i];
                    let more = d.is_ascii_alphanumeric()
                        || matches!(d, b'_' | b':')
                        || (numeric && matches!(d, b'.' | b'-' | b'+'));
                    if !more {
                        break;
                    }
                    i += 1;
                }
                toks.push((Tok::Word(&text[start..i]), line));
            }
            _ => {
                let ch = text[i..].chars().next().unwrap_or('?');
                toks.push((Tok::Punct(ch), line));
                i += ch.len_utf8();
            }
        }
    }
    Ok(toks)
}

/// Parses `.usda` text; `path` names it in errors.
fn parse(text: &str, path: &Path, opts: &ImportOptions) -> Result<Groom, GroomError> {
    if !text.starts_with("#usda") {
        return Err(bad(
            path,
            FileLocation::Line(1),
            "does not start with `#usda 1.0`: this is not a USD text file (binary .usdc/.usdz: \
             convert with `usdcat -o file.usda`)",
        ));
    }
    let toks = tokenize(text, path)?;
    let closing = closing_brackets(&toks);
    let skip_balanced = |at: usize, open: char, close: char| match closing[at] {
        NEVER_CLOSED => Err(bad(
            path,
            FileLocation::Line(toks[at].1),
            format!("`{open}` is never closed by `{close}`"),
        )),
        end => Ok(end),
    };
    let mut curves = Vec::new();
    let mut found = false;
    let mut i = 0;
    while i + 2 < toks.len() {
        let is_curves = toks[i].0 == Tok::Word("def")
            && toks[i + 1].0 == Tok::Word("BasisCurves")
            && matches!(toks[i + 2].0, Tok::Str(_));
        if !is_curves {
            i += 1;
            continue;
        }
        found = true;
        let def_line = toks[i].1;
        let mut j = i + 3;
        if toks.get(j).map(|t| &t.0) == Some(&Tok::Punct('(')) {
            j = skip_balanced(j, '(', ')')?;
        }
        if toks.get(j).map(|t| &t.0) != Some(&Tok::Punct('{')) {
            return Err(bad(
                path,
                FileLocation::Line(def_line),
                "`def BasisCurves` is not followed by its `{ … }` body",
            ));
        }
        let end = skip_balanced(j, '{', '}')?;
        let body = j + 1..end - 1;
        curves.extend(read_prim(&toks, &closing, body, def_line, path, opts)?);
        // Nested prims are found by continuing inside the body.
        i = j + 1;
    }
    if !found {
        return Err(bad(
            path,
            FileLocation::File,
            "has no `def BasisCurves` prim: export the hair as USD curves",
        ));
    }
    Groom::new(curves)
}

/// [`closing_brackets`] entry of a bracket that is never closed (and of every other token).
const NEVER_CLOSED: usize = usize::MAX;

/// For each token: if it opens a `{` or `(`, the index just past its matching closer, else
/// [`NEVER_CLOSED`]. One pass, so nested prims cost no more than flat ones (scanning for each
/// prim's end was quadratic in the nesting depth).
fn closing_brackets(toks: &[(Tok, usize)]) -> Vec<usize> {
    let mut closing = vec![NEVER_CLOSED; toks.len()];
    let (mut braces, mut parens) = (Vec::new(), Vec::new());
    for (k, (t, _)) in toks.iter().enumerate() {
        match t {
            Tok::Punct('{') => braces.push(k),
            Tok::Punct('(') => parens.push(k),
            Tok::Punct('}') => {
                if let Some(open) = braces.pop() {
                    closing[open] = k + 1;
                }
            }
            Tok::Punct(')') => {
                if let Some(open) = parens.pop() {
                    closing[open] = k + 1;
                }
            }
            _ => {}
        }
    }
    closing
}

/// The curves of the prim whose body (the tokens between its braces) is `toks[body]`; nested
/// prims' braces are jumped over with `closing` ([`closing_brackets`]), so their attributes are
/// skipped without being scanned.
fn read_prim(
    toks: &[(Tok, usize)],
    closing: &[usize],
    body: std::ops::Range<usize>,
    def_line: usize,
    path: &Path,
    opts: &ImportOptions,
) -> Result<Vec<Vec<Vector3<f32>>>, GroomError> {
    let mut counts: Option<(Vec<usize>, usize)> = None;
    let mut points: Option<(Vec<Vector3<f32>>, usize)> = None;
    let end = body.end;
    let mut k = body.start;
    while k < end {
        let at = k;
        k += 1;
        match toks[at].0 {
            // A nested block (a child prim): jump past it (it is balanced inside the body).
            Tok::Punct('{') if closing[at] != NEVER_CLOSED => k = closing[at].min(end),
            Tok::Word(name @ ("curveVertexCounts" | "points"))
                if toks.get(at + 1).map(|t| &t.0) == Some(&Tok::Punct('=')) =>
            {
                let line = toks[at].1;
                let numbers = array_numbers(&toks[at + 2..end], line, path)?;
                if name == "points" {
                    if numbers.len() % 3 != 0 {
                        return Err(bad(
                            path,
                            FileLocation::Line(line),
                            "`points` must be a list of (x, y, z) triples",
                        ));
                    }
                    let pts = numbers
                        .chunks_exact(3)
                        .map(|c| {
                            let p = [c[0].0, c[1].0, c[2].0];
                            if p.iter().all(|x| x.is_finite()) {
                                Ok(to_world(p, opts))
                            } else {
                                Err(bad(
                                    path,
                                    FileLocation::Line(c[0].1),
                                    format!("a point has a non-finite coordinate {p:?}"),
                                ))
                            }
                        })
                        .collect::<Result<Vec<_>, _>>()?;
                    points = Some((pts, line));
                } else {
                    let ints = numbers
                        .iter()
                        .map(|&(x, l)| {
                            if x.fract() == 0.0 && (0.0..1e9).contains(&x) {
                                Ok(x as usize)
                            } else {
                                Err(bad(
                                    path,
                                    FileLocation::Line(l),
                                    format!("curveVertexCounts holds {x}, not a count"),
                                ))
                            }
                        })
                        .collect::<Result<Vec<_>, _>>()?;
                    counts = Some((ints, line));
                }
            }
            _ => {}
        }
    }
    let missing = |what: &str| {
        bad(
            path,
            FileLocation::Line(def_line),
            format!(
                "this BasisCurves prim has no default `{what}` value (time samples are not read)"
            ),
        )
    };
    let (counts, counts_line) = counts.ok_or_else(|| missing("curveVertexCounts"))?;
    let (points, _) = points.ok_or_else(|| missing("points"))?;
    let total: usize = counts.iter().sum();
    if total != points.len() {
        return Err(bad(
            path,
            FileLocation::Line(counts_line),
            format!(
                "curveVertexCounts add up to {total} points but `points` holds {}: they must agree",
                points.len()
            ),
        ));
    }
    let mut curves = Vec::with_capacity(counts.len());
    let mut start = 0;
    for (c, &n) in counts.iter().enumerate() {
        if n < 2 {
            return Err(bad(
                path,
                FileLocation::Line(counts_line),
                format!("curve {c} has {n} vertex(es); a curve needs at least 2"),
            ));
        }
        curves.push(points[start..start + n].to_vec());
        start += n;
    }
    Ok(curves)
}

/// The numbers of the array value starting at `toks[0]` (`[1, 2]` or `[(1, 2, 3), …]`), each with
/// its line; parentheses are flattened.
fn array_numbers(
    toks: &[(Tok, usize)],
    line: usize,
    path: &Path,
) -> Result<Vec<(f32, usize)>, GroomError> {
    if toks.first().map(|t| &t.0) != Some(&Tok::Punct('[')) {
        return Err(bad(
            path,
            FileLocation::Line(line),
            "expected an array value `[ … ]`",
        ));
    }
    let mut out = Vec::new();
    for (t, l) in &toks[1..] {
        match t {
            Tok::Punct(']') => return Ok(out),
            Tok::Punct('(' | ')' | ',') => {}
            Tok::Word(w) => {
                let x: f32 = w.parse().map_err(|_| {
                    bad(
                        path,
                        FileLocation::Line(*l),
                        format!("`{w}` is not a number"),
                    )
                })?;
                out.push((x, *l));
            }
            other => {
                return Err(bad(
                    path,
                    FileLocation::Line(*l),
                    format!("unexpected {other:?} in an array"),
                ))
            }
        }
    }
    Err(bad(
        path,
        FileLocation::Line(line),
        "the array is never closed by `]`",
    ))
}

/// The `.usda` text of `groom`.
fn encode(groom: &Groom, opts: &ImportOptions) -> String {
    let up = match opts.up_axis {
        UpAxis::Y => "Y",
        UpAxis::Z => "Z",
    };
    let mut out = format!(
        "#usda 1.0\n(\n    defaultPrim = \"hair\"\n    metersPerUnit = {:?}\n    upAxis = \"{up}\"\n)\n\n\
         def BasisCurves \"hair\"\n{{\n    uniform token type = \"linear\"\n    int[] curveVertexCounts = [",
        opts.scale
    );
    let counts: Vec<String> = groom.curves().iter().map(|c| c.len().to_string()).collect();
    out.push_str(&counts.join(", "));
    out.push_str("]\n    point3f[] points = [");
    for (k, p) in groom.curves().iter().flatten().enumerate() {
        let [x, y, z] = to_file(p, opts);
        let sep = if k == 0 { "" } else { ", " };
        let _ = write!(out, "{sep}({x:?}, {y:?}, {z:?})");
    }
    out.push_str("]\n}\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::test_support::{assert_round_trip, tricky_groom};

    fn parse_err(text: &str) -> String {
        parse(text, Path::new("h.usda"), &ImportOptions::default())
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn write_then_read_is_bit_exact() {
        assert_round_trip(&tricky_groom(), |g, opts| {
            let text = encode(g, opts);
            parse(&text, Path::new("m.usda"), opts).unwrap_or_else(|e| panic!("{e}\n{text}"))
        });
    }

    #[test]
    fn reads_nested_prims_and_skips_the_rest() {
        let text = r#"#usda 1.0
(
    doc = """a "groom" # not a comment, née Zoë"""
    customLayerData = { string note = "crème \"brûlée\" ☃" }
    upAxis = "Y"
)
def Xform "root" ( kind = "component" )
{
    double3 xformOp:translate = (1, 2, 3)
    def BasisCurves "a" (
        prepend apiSchemas = ["MaterialBindingAPI"]
    )
    {
        rel material:binding = </root/mat>
        uniform token type = "cubic"
        int[] curveVertexCounts = [2]   # one curve
        point3f[] points = [(0, 0, 0), (1e-3, -2.5e+1, .5)]
        point3f[] points.timeSamples = { 1: [(9, 9, 9), (9, 9, 9)] }
        float[] widths = [0.1, 0.1]
        def BasisCurves "b"
        {
            int[] curveVertexCounts = [3]
            point3f[] points = [(1, 1, 1), (2, 2, 2), (3, 3, 3)]
        }
    }
}
"#;
        let g = parse(text, Path::new("n.usda"), &ImportOptions::default()).unwrap();
        assert_eq!(g.len(), 2);
        assert_eq!(g.curves()[0][1], Vector3::new(1e-3, -25.0, 0.5));
        assert_eq!(g.curves()[1][2], Vector3::new(3.0, 3.0, 3.0));
    }

    #[test]
    fn bad_files_are_named_with_lines() {
        assert!(parse_err("PXR-USDC binary").contains("not a USD text file"));
        assert!(parse_err("#usda 1.0\ndef Mesh \"m\" {}\n").contains("no `def BasisCurves`"));
        let head = "#usda 1.0\ndef BasisCurves \"c\"\n{\n";
        let msg = parse_err(&format!("{head}    int[] curveVertexCounts = [3]\n    point3f[] points = [(0,0,0), (1,1,1)]\n}}\n"));
        assert!(
            msg.contains("line 4") && msg.contains("must agree"),
            "{msg}"
        );
        let msg = parse_err(&format!("{head}    int[] curveVertexCounts = [1, 1]\n    point3f[] points = [(0,0,0), (1,1,1)]\n}}\n"));
        assert!(msg.contains("curve 0 has 1 vertex"), "{msg}");
        let msg = parse_err(&format!("{head}    int[] curveVertexCounts = [2]\n    point3f[] points = [(0,0,0),\n (nan,1,1)]\n}}\n"));
        assert!(
            msg.contains("line 6") && msg.contains("non-finite"),
            "{msg}"
        );
        let msg = parse_err(&format!("{head}    int[] curveVertexCounts = [2]\n}}\n"));
        assert!(msg.contains("line 2") && msg.contains("`points`"), "{msg}");
        let msg = parse_err(&format!(
            "{head}    int[] curveVertexCounts = [2]\n    point3f[] points = [(0,0,0), (1,1,1)\n"
        ));
        assert!(msg.contains("never closed"), "{msg}");
        assert!(parse_err("#usda 1.0\ndef BasisCurves \"unterminated\n").contains("not closed"));
        let msg = parse_err(&format!("{head}    int[] curveVertexCounts = [2.5]\n    point3f[] points = [(0,0,0), (1,1,1)]\n}}\n"));
        assert!(msg.contains("not a count"), "{msg}");
    }

    #[test]
    fn deep_nesting_costs_linear_time() {
        // 20 000 prims, each inside the previous: scanning every prim's body to its end took
        // time quadratic in the depth (about 10^10 token visits here).
        let depth = 20_000;
        let mut text = String::from("#usda 1.0\n");
        for _ in 0..depth {
            text.push_str(
                "def BasisCurves \"c\" {\n int[] curveVertexCounts = [2]\n \
                 point3f[] points = [(0, 0, 0), (0, 0, 1)]\n",
            );
        }
        text.push_str(&"}\n".repeat(depth));
        let start = std::time::Instant::now();
        let groom = parse(&text, Path::new("deep.usda"), &ImportOptions::default()).unwrap();
        assert_eq!(groom.len(), depth);
        assert!(start.elapsed().as_secs_f64() < 5.0, "{:?}", start.elapsed());
    }

    #[test]
    fn every_truncation_is_an_error_not_a_panic() {
        let g = Groom::new(vec![vec![Vector3::zeros(), Vector3::x()]]).unwrap();
        let text = encode(&g, &ImportOptions::default());
        // Every prefix short of the closing `}` (the last character is a newline).
        for n in 0..text.len() - 1 {
            assert!(
                parse(&text[..n], Path::new("t.usda"), &ImportOptions::default()).is_err(),
                "prefix {n}"
            );
        }
        for i in 0..text.len() {
            for c in ["[", "]", "(", "{", "}", "\"", "#", "-", "x"] {
                let bad = format!("{}{c}{}", &text[..i], &text[i + 1..]);
                let _ = parse(&bad, Path::new("t.usda"), &ImportOptions::default());
            }
        }
    }
}
