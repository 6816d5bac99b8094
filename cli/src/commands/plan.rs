//! `hairsys plan`: the arguments, the table and the JSON of `hairsys::plan`.

use std::path::{Path, PathBuf};

use hairsys::plan::study::{knee, sim_hair_levels};
use hairsys::plan::{plan, verify, write::chosen_scene, Candidate, Plan, PlanOptions, Verdict};
use hairsys::scene::SceneFile;

use crate::args::parse_range;
use crate::error::CliError;
use crate::{output, Context};

/// Arguments of `plan`.
#[derive(Debug, Clone, clap::Args)]
pub struct PlanArgs {
    /// Scene file (TOML).
    scene: PathBuf,
    /// Largest accepted error (worst frame's RMS position error), e.g. 2mm, 0.5cm, 0.002.
    #[arg(long, value_parser = parse_length)]
    tolerance: f32,
    /// Frames to probe FIRST-LAST [default: the scene's first frame and the 12 after it].
    #[arg(long, value_parser = parse_range)]
    frames: Option<(u32, u32)>,
    /// Write the scene with the chosen settings here (comments and layout kept).
    #[arg(long, value_name = "OUT.toml")]
    write: Option<PathBuf>,
    /// Also re-run the chosen scene on the whole groom against the reference, over the
    /// probed frames and over the whole shot (costs two full-groom reference runs).
    #[arg(long)]
    verify: bool,
    /// Instead of planning, the sim-hair study: render hairs interpolated from each of these
    /// sim-hair counts against every strand simulated, with the scene's settings, over
    /// --frames (default: the whole shot), e.g. --levels 50,100,200,500,1000,2000.
    #[arg(long, value_delimiter = ',', value_name = "COUNTS")]
    levels: Vec<usize>,
    /// Print nothing but errors.
    #[arg(long, conflicts_with = "json")]
    quiet: bool,
    /// Print the plan as JSON on stdout.
    #[arg(long)]
    json: bool,
}

/// A length with an optional unit (`2mm`, `0.2 cm`, `0.002`, `0.002m`), in meters.
pub fn parse_length(s: &str) -> Result<f32, NotALength> {
    let t = s.trim();
    let (number, scale) = [
        ("mm", 1e-3),
        ("cm", 1e-2),
        ("um", 1e-6),
        ("µm", 1e-6),
        ("m", 1.0),
    ]
    .iter()
    .find_map(|(unit, scale)| t.strip_suffix(unit).map(|n| (n.trim(), *scale)))
    .unwrap_or((t, 1.0));
    match number.parse::<f32>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v * scale),
        _ => Err(NotALength {
            given: s.to_string(),
        }),
    }
}

/// A `--tolerance` value that is not a length > 0.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("`{given}` is not a length > 0; write e.g. 2mm, 0.5cm or 0.002 (meters)")]
pub struct NotALength {
    /// The value given.
    pub given: String,
}

/// Runs the plan and prints it; no candidate within the tolerance is a failed run.
pub fn run(args: &PlanArgs, ctx: &Context) -> Result<(), CliError> {
    let mut scene = SceneFile::load(&args.scene)?;
    scene.budget = ctx.budget;
    if !args.levels.is_empty() {
        return levels(&scene, args);
    }
    let mut opts = PlanOptions::new(args.tolerance);
    opts.frames = args.frames;
    let chatty = !args.quiet && !args.json;
    let mut count = 0;
    let mut progress = |what: &str| {
        count += 1;
        if chatty {
            eprintln!("probe {count}: {what}");
        }
    };
    let p = plan(&scene, &opts, &mut progress)?;
    let mut written = None;
    if let (Some(out), Some(c)) = (&args.write, p.choice()) {
        let note = format!(
            "hairsys plan, tolerance {:.2} mm: {}, {} sim hairs (measured {:.2} mm RMS worst frame)",
            p.tolerance * 1e3,
            c.method,
            c.sim_hairs,
            c.errors.rms_max * 1e3
        );
        let text = chosen_scene(&scene, c, p.strands, &note)?;
        write_file(out, &text)?;
        written = Some(out.display().to_string());
    }
    let mut verified = Vec::new();
    if let (true, Some(c)) = (args.verify, p.choice()) {
        let text = chosen_scene(&scene, c, p.strands, "verify")?;
        let chosen = SceneFile::parse(&text, &scene.origin, scene.base_dir.clone())?;
        let last = scene.scene.scene.frames[1];
        let mut windows = vec![p.probe_frames];
        if p.probe_frames.1 != last {
            windows.push((p.probe_frames.0, last));
        }
        for frames in windows {
            if chatty {
                eprintln!("verify: the whole groom, frames {}-{}", frames.0, frames.1);
            }
            let e = verify::rerun(&scene, &chosen, p.reference, frames, opts.samples)?;
            verified.push((frames, e));
        }
    }
    if args.json {
        let mut v = serde_json::to_value(&p).expect("plans serialise");
        v["written"] = serde_json::json!(written);
        v["verified"] = serde_json::json!(verified
            .iter()
            .map(|(f, e)| serde_json::json!({ "frames": [f.0, f.1], "errors": e }))
            .collect::<Vec<_>>());
        output::line(&serde_json::to_string_pretty(&v).expect("values serialise"));
    } else if !args.quiet {
        output::block(&table(&p));
        if let Some(w) = &written {
            output::line(&format!("wrote {w}"));
        }
        for (f, e) in &verified {
            output::line(&format!(
                "verified on the whole groom, frames {}-{}: {} mm RMS worst frame (tip {} mm)",
                f.0,
                f.1,
                mm(e.rms_max),
                mm(e.tip_max)
            ));
        }
    }
    match p.choice() {
        Some(_) => Ok(()),
        None => Err(CliError::failed(format!(
            "no candidate met {:.2} mm; the closest is in the table (raise --tolerance)",
            p.tolerance * 1e3
        ))),
    }
}

/// The sim-hair study (`--levels`): a markdown table on stdout, or JSON.
fn levels(scene: &SceneFile, args: &PlanArgs) -> Result<(), CliError> {
    let frames = args
        .frames
        .unwrap_or((scene.scene.scene.frames[0], scene.scene.scene.frames[1]));
    if !args.quiet && !args.json {
        eprintln!(
            "simulating every strand, then {} sim-hair counts, frames {}-{}",
            args.levels.len(),
            frames.0,
            frames.1
        );
    }
    let rows = sim_hair_levels(scene, frames, &args.levels, 8)?;
    // The full run is the reference itself (zero error by construction): the knee is among
    // the fewer counts.
    let k = knee(&rows[..rows.len() - 1]);
    if args.json {
        output::line(
            &serde_json::to_string_pretty(&serde_json::json!({ "rows": rows, "knee": k }))
                .expect("values serialise"),
        );
    } else if !args.quiet {
        let mut t = String::from(
            "| sim hairs | CPU ms/frame | worst-frame RMS mm | RMS mm | worst-frame tip RMS mm |\n|---|---|---|---|---|\n",
        );
        for (i, r) in rows.iter().enumerate() {
            t += &format!(
                "| {}{} | {:.1} | {} | {} | {} |\n",
                r.sim_hairs,
                if Some(i) == k { " (knee)" } else { "" },
                r.ms_per_frame,
                mm(r.errors.rms_max),
                mm(r.errors.rms),
                mm(r.errors.tip_max)
            );
        }
        output::block(&t);
    }
    Ok(())
}

/// Writes the chosen scene to `out`.
fn write_file(out: &Path, text: &str) -> Result<(), CliError> {
    std::fs::write(out, text)
        .map_err(|e| CliError::failed(format!("{}: cannot write: {e}", out.display())))
}

fn mm(v: f32) -> String {
    format!("{:.2}", v * 1e3)
}

fn row(c: &Candidate) -> String {
    let m = &c.method;
    let name = m.to_string();
    let name = name.split(',').next().unwrap_or("");
    let substeps = match m.substeps {
        Some(n) => n.to_string(),
        None => format!("auto ({})", c.substeps_run),
    };
    let verdict = match &c.verdict {
        Verdict::Chosen => "CHOSEN".to_string(),
        Verdict::Within => "within".to_string(),
        Verdict::Exceeds => "exceeds".to_string(),
        Verdict::Failed(e) => format!("failed: {e}"),
    };
    format!(
        "{name:<15} {substeps:>10} {:>8} {:>9} {:>9} {:>9} {:>10.2} {verdict}\n",
        m.segments,
        c.sim_hairs,
        mm(c.errors.rms_max),
        mm(c.errors.tip_max),
        c.predicted_seconds
    )
}

/// The plan as text: probe, reference, choice, the table of candidates, what was not probed.
pub fn table(p: &Plan) -> String {
    let mut t = format!(
        "plan for {}, tolerance {} mm (worst frame's RMS position error)\n",
        p.scene,
        mm(p.tolerance)
    );
    t += &format!(
        "probe: {} of {} strands in {} patches, frames {}-{}; reference: {} \
         (its error at half the substeps: {} mm)\n",
        p.probe_strands,
        p.strands,
        p.patches,
        p.probe_frames.0,
        p.probe_frames.1,
        p.reference,
        mm(p.reference_check.rms_max)
    );
    let s = &p.scene_method;
    t += &format!(
        "scene as written: {}: {} mm, predicted {:.1} s CPU for {} frames\n",
        s.method,
        mm(s.errors.rms_max),
        s.predicted_seconds,
        p.run_frames
    );
    match p.choice() {
        Some(c) => {
            t += &format!(
                "chosen: {}, {} sim hairs: {} mm RMS (tip {} mm), predicted {:.1} s CPU ({:.1}x cheaper than the scene as written)\n",
                c.method,
                c.sim_hairs,
                mm(c.errors.rms_max),
                mm(c.errors.tip_max),
                c.predicted_seconds,
                s.predicted_seconds / c.predicted_seconds
            )
        }
        None => t += "chosen: none within tolerance\n",
    }
    t += &format!(
        "\n{:<15} {:>10} {:>8} {:>9} {:>9} {:>9} {:>10} verdict\n",
        "method", "substeps", "segments", "sim hairs", "rms mm", "tip mm", "cpu s"
    );
    for c in &p.candidates {
        t += &row(c);
    }
    for w in &p.warnings {
        t += &format!("warning: {w}\n");
    }
    t += "\nnot probed:\n";
    for (what, why) in &p.not_probed {
        t += &format!("  {what}: {why}\n");
    }
    t += &format!(
        "plan took {:.2} s CPU ({:.1} % of the predicted {:.1} s CPU of the run as written)\n",
        p.seconds,
        100.0 * p.seconds / s.predicted_seconds,
        s.predicted_seconds
    );
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_take_units() {
        assert_eq!(parse_length("2mm").unwrap(), 2e-3);
        assert!((parse_length("0.5 cm").unwrap() - 5e-3).abs() < 1e-9);
        assert_eq!(parse_length("0.002").unwrap(), 0.002);
        assert!(parse_length("-1mm").is_err());
        assert!(parse_length("two").is_err());
    }
}
