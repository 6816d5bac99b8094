//! Writing the chosen settings into the user's scene text.
//!
//! The scene is edited line by line instead of re-serialised, so the user's comments, key order
//! and layout stay: a key's value is replaced in place (its trailing comment kept), a missing
//! key is added at the end of its section, a missing section at the end of the file. Only the
//! simple values `plan` writes (numbers, booleans, strings without `#`) are handled; the result
//! is parsed again before it is returned.

use crate::plan::probe::same_material;
use crate::plan::Candidate;
use crate::scene::integrator::integrator_name;
use crate::scene::SceneFile;
use crate::Error;

/// `scene`'s text with `choice` written into it (`[solver] integrator`, `substeps`,
/// `inextensibility`; `[hair] segments` with `[physics]` stiffnesses for the same material,
/// and `[hair] count` or `[sim_hairs] count`; with fewer sim hairs
/// than strands and no `[children]`, interpolated render children as many as the strands were),
/// and a comment line saying what the plan chose. `total` is the scene's strand count.
pub fn chosen_scene(
    scene: &SceneFile,
    choice: &Candidate,
    total: usize,
    note: &str,
) -> Result<String, Error> {
    let s = &scene.scene;
    let m = &choice.method;
    let mut text = scene.text.clone();
    text = set_key(
        &text,
        "solver",
        "integrator",
        &format!("\"{}\"", integrator_name(m.integrator)),
    );
    text = set_key(
        &text,
        "solver",
        "substeps",
        &m.substeps.map_or("\"auto\"".to_string(), |n| n.to_string()),
    );
    if m.inextensible || s.solver.inextensibility {
        text = set_key(
            &text,
            "solver",
            "inextensibility",
            &m.inextensible.to_string(),
        );
    }
    if let Some(h) = &s.hair {
        if h.segments != m.segments {
            text = set_key(&text, "hair", "segments", &m.segments.to_string());
            let p = same_material(&s.physics, h.segments, m.segments);
            text = set_key(
                &text,
                "physics",
                "stretch_stiffness",
                &p.stretch_stiffness.to_string(),
            );
            text = set_key(
                &text,
                "physics",
                "bend_stiffness",
                &p.bend_stiffness.to_string(),
            );
        }
    }
    if choice.sim_hairs < total {
        if s.hair.is_some() {
            text = set_key(&text, "hair", "count", &choice.sim_hairs.to_string());
        } else if s.sim_hairs.is_some() {
            text = set_key(&text, "sim_hairs", "count", &choice.sim_hairs.to_string());
        }
        if s.children.is_none() {
            text = set_key(&text, "children", "mode", "\"interpolated\"");
            text = set_key(&text, "children", "count", &total.to_string());
        }
    }
    let mut lines: Vec<&str> = text.lines().collect();
    let at = lines
        .iter()
        .position(|l| l.trim_start().starts_with("version"))
        .map_or(0, |i| i + 1);
    let comment = format!("# {note}");
    lines.insert(at, &comment);
    let mut out = lines.join("\n");
    out.push('\n');
    SceneFile::parse(&out, &scene.origin, scene.base_dir.clone())?;
    Ok(out)
}

/// The header name of a line `[name]` (comments allowed after it), if it is one.
fn header(line: &str) -> Option<&str> {
    let t = line.split('#').next().unwrap_or("").trim();
    (t.starts_with('[') && t.ends_with(']') && !t.starts_with("[["))
        .then(|| t[1..t.len() - 1].trim())
        .or_else(|| t.starts_with("[[").then_some(""))
}

/// `text` with `key = value` set in table `section` (see the module docs).
pub fn set_key(text: &str, section: &str, key: &str, value: &str) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let start = lines.iter().position(|l| header(l) == Some(section));
    let Some(start) = start else {
        let mut out = text.trim_end().to_string();
        out.push_str(&format!("\n\n[{section}]\n{key} = {value}\n"));
        return out;
    };
    let end = lines[start + 1..]
        .iter()
        .position(|l| header(l).is_some())
        .map_or(lines.len(), |i| start + 1 + i);
    for line in &mut lines[start + 1..end] {
        let Some((lhs, rhs)) = line.split_once('=') else {
            continue;
        };
        if lhs.trim() != key || lhs.trim_start().starts_with('#') {
            continue;
        }
        let comment = rhs.find('#').map(|i| rhs[i..].to_string());
        let indent = &lhs[..lhs.len() - lhs.trim_start().len()];
        let mut new = format!("{indent}{key} = {value}");
        if let Some(c) = comment {
            let width = lhs.len() + rhs.find('#').unwrap_or(0) + 1;
            while new.len() + 1 < width {
                new.push(' ');
            }
            new.push(' ');
            new.push_str(&c);
        }
        *line = new;
        return lines.join("\n") + "\n";
    }
    // Not there: after the section's last key line.
    let last_key = (start + 1..end)
        .rev()
        .find(|&i| {
            let t = lines[i].trim_start();
            !t.is_empty() && !t.starts_with('#')
        })
        .unwrap_or(start);
    lines.insert(last_key + 1, format!("{key} = {value}"));
    lines.join("\n") + "\n"
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "version = 1\n[solver]\nsubsteps = \"auto\"   # the bound\n\
                        # inextensibility = true\n\n[hair]\ncount = 10\n";

    #[test]
    fn a_value_is_replaced_and_its_comment_kept() {
        let out = set_key(TEXT, "solver", "substeps", "12");
        assert!(out.contains("substeps = 12"), "{out}");
        assert!(out.contains("# the bound"), "{out}");
        assert!(out.contains("# inextensibility = true"), "{out}");
    }

    #[test]
    fn a_missing_key_goes_into_its_section_not_onto_a_commented_one() {
        let out = set_key(TEXT, "solver", "inextensibility", "true");
        let solver = &out[out.find("[solver]").unwrap()..out.find("[hair]").unwrap()];
        assert!(solver.contains("\ninextensibility = true\n"), "{out}");
        assert!(out.contains("# inextensibility = true"), "{out}");
    }

    #[test]
    fn a_missing_section_is_appended() {
        let out = set_key(TEXT, "children", "count", "40");
        assert!(out.ends_with("[children]\ncount = 40\n"), "{out}");
    }

    #[test]
    fn a_subtable_is_not_its_parent() {
        let text = "[hair.style]\ncount = 3\n[hair]\ncount = 10\n";
        let out = set_key(text, "hair", "count", "5");
        assert_eq!(out, "[hair.style]\ncount = 3\n[hair]\ncount = 5\n");
    }
}
