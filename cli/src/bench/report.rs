//! The bench's files: `bench.md` (the tables, with what "converged" means), `bench.json` (every
//! number) and, through [`super::charts`], `pareto.png` and `stability_map.png`.

use std::fmt::Write as _;
use std::path::Path;

use super::charts;
use super::stability::{Grid, FPS};
use super::{BenchError, BenchReport, Outcome, REFERENCE_FACTOR};

/// File names written into the output directory.
pub const FILES: [&str; 4] = ["pareto.png", "stability_map.png", "bench.md", "bench.json"];

fn write(path: &Path, text: &str) -> Result<(), BenchError> {
    std::fs::write(path, text).map_err(|e| BenchError::Write {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// Creates the output directory `out` if missing.
pub fn create_dir(out: &Path) -> Result<(), BenchError> {
    std::fs::create_dir_all(out).map_err(|e| BenchError::Write {
        path: out.to_path_buf(),
        message: e.to_string(),
    })
}

/// Writes the charts and tables of `report` into `out` (created if missing).
pub fn write_all(report: &BenchReport, grid: &Grid, out: &Path) -> Result<(), BenchError> {
    create_dir(out)?;
    charts::pareto(report, &out.join(FILES[0]))?;
    charts::stability_map(report, grid, &out.join(FILES[1]))?;
    write(&out.join(FILES[2]), &markdown(report, grid))?;
    let json = serde_json::to_string_pretty(report).map_err(|e| BenchError::Write {
        path: out.join(FILES[3]),
        message: e.to_string(),
    })?;
    write(&out.join(FILES[3]), &json)
}

fn sci(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if x.is_infinite() {
        "∞".into()
    } else {
        format!("{x:.2e}")
    }
}

/// The Markdown report: cases, references and their convergence, one row per run, the stability
/// boundary per stiffness.
pub fn markdown(r: &BenchReport, grid: &Grid) -> String {
    let mut s = String::new();
    let cmd = if r.quick {
        "hairsys bench --quick"
    } else {
        "hairsys bench"
    };
    let _ = writeln!(s, "# `{cmd}`: speed against accuracy\n");
    let _ = writeln!(
        s,
        "Made by `{cmd} --out DIR` in {:.0} s. Costs are wall-clock times of the solver alone on \
         the machine that ran it; errors do not depend on the machine.\n",
        r.seconds
    );
    let _ = writeln!(s, "## Cases\n");
    for (name, title) in &r.cases {
        let _ = writeln!(s, "- **{name}**: {title}");
    }
    let _ = writeln!(
        s,
        "\n## Methods\n\nWhat each runs on the head case (as `Solver::components` reports it):\n"
    );
    for (name, components) in &r.methods {
        let _ = writeln!(s, "- **{name}**: {components}");
    }
    let _ = writeln!(
        s,
        "\n## References\n\nEach method is measured against its **reference**: the same case, \
         the same model, advanced by semi-implicit Euler at {REFERENCE_FACTOR}× the finest substep \
         count charted. A reference counts as **converged** when halving its step changes it \
         (position RMS over the sample frames) by less than the smallest error charted against \
         it.\n"
    );
    let _ = writeln!(
        s,
        "| case | reference | substeps/frame | change when halved (m) | smallest error charted (m) | converged |"
    );
    let _ = writeln!(s, "|---|---|---:|---:|---:|---|");
    for c in &r.references {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} |",
            c.case,
            c.reference,
            c.substeps,
            sci(c.halving_change),
            sci(c.smallest_error),
            if c.converged { "yes" } else { "**no**" }
        );
    }
    let _ = writeln!(
        s,
        "\n## Runs\n\nPosition error: RMS of `|x − x_ref|` over free points and sample frames. \
         Stretch: largest `len/rest − 1`. Energy drift: `(E(T) − E_ref(T)) / Σ m g L`. \
         Penetration: deepest point centre inside the head. `auto` marks `substeps = \"auto\"`.\n"
    );
    let _ = writeln!(
        s,
        "| case | method | substeps/frame | dt (s) | ms/frame | M point-substeps/s | position error (m) | max stretch (%) | energy drift | max penetration (mm) |"
    );
    let _ = writeln!(s, "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    for run in &r.runs {
        let substeps = if run.auto {
            format!("{} (auto)", run.substeps)
        } else {
            run.substeps.to_string()
        };
        match &run.outcome {
            Outcome::Stable { cost, errors } => {
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | {} | {:.3} | {:.1} | {} | {:.3} | {} | {:.2} |",
                    run.case,
                    run.method,
                    substeps,
                    sci(run.dt),
                    cost.ms_per_frame,
                    cost.point_substeps_per_s / 1e6,
                    sci(errors.position_rms),
                    100.0 * errors.max_stretch,
                    sci(errors.energy_drift),
                    1e3 * errors.max_penetration,
                );
            }
            Outcome::Unstable { .. } => {
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | {} | unstable | | | | | |",
                    run.case,
                    run.method,
                    substeps,
                    sci(run.dt)
                );
            }
        }
    }
    let _ = writeln!(
        s,
        "\n## Where `substeps = \"auto\"` lands\n\n`auto` takes 0.8 × the predicted bound. With fewer substeps than the bound allows, the \
         default method is unstable; with more, its error falls only as 1/substeps while the cost \
         grows as substeps: the knee of its front is just inside the bound.\n"
    );
    let _ = writeln!(
        s,
        "| case | auto: substeps/frame | auto: position error (m) | fewest stable substeps on the ladder | its error (m) |"
    );
    let _ = writeln!(s, "|---|---:|---:|---:|---:|");
    for (case, _) in &r.cases {
        let default = |run: &&super::Run| &run.case == case && run.method == "semi-implicit Euler";
        let auto = r.runs.iter().filter(default).find(|x| x.auto);
        let first = r
            .runs
            .iter()
            .filter(default)
            .filter(|x| !x.auto)
            .find_map(|x| x.stable().map(|(_, e)| (x.substeps, e.position_rms)));
        let (a_n, a_e) = auto
            .and_then(|x| {
                x.stable()
                    .map(|(_, e)| (x.substeps.to_string(), sci(e.position_rms)))
            })
            .unwrap_or(("unstable".into(), String::new()));
        let (f_n, f_e) = first
            .map(|(n, e)| (n.to_string(), sci(e)))
            .unwrap_or(("none".into(), String::new()));
        let _ = writeln!(s, "| {case} | {a_n} | {a_e} | {f_n} | {f_e} |");
    }
    let _ = writeln!(
        s,
        "\n## Stability\n\nProbe: 16 segments of 1 cm, 10 mg per point, no bending, released \
         horizontally under gravity, {} frames at {FPS} fps. Predicted bound `dt < 2/ω`, \
         `ω² = 4 (k_stretch + 4 k_bend)/m_min`; observed: the longest substep from which every \
         shorter one was stable.\n",
        grid.frames
    );
    let _ = writeln!(
        s,
        "| method | k (N/m) | predicted dt (s) | observed dt (s) | observed / predicted |"
    );
    let _ = writeln!(s, "|---|---:|---:|---:|---:|");
    for m in &r.stability {
        for (row, &k) in grid.stiffness.iter().enumerate() {
            let pred = m.predicted_dt[row];
            let (obs, ratio) = match m.observed_dt[row] {
                Some(o) if pred.is_finite() => (sci(o), sci(o / pred)),
                Some(o) => (sci(o), "no bound".into()),
                None => ("none stable".into(), String::new()),
            };
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} |",
                m.method,
                sci(k),
                sci(pred),
                obs,
                ratio
            );
        }
        let inside = m.fails_inside_bound(grid);
        if !inside.is_empty() {
            let ks: Vec<String> = inside.iter().map(|&k| sci(k)).collect();
            let _ = writeln!(
                s,
                "| {} fails inside the predicted bound at k = {} | | | | |",
                m.method,
                ks.join(", ")
            );
        }
    }
    s
}
