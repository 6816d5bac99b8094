//! The bench's files: `bench.md` (the tables, with what "converged" means), `bench.json` (every
//! number) and, through [`crate::charts`], `pareto.png`, `stability_map.png` and `segments.png`.

use std::fmt::Write as _;
use std::path::Path;

use crate::charts;
use hair_core::ProjectionReport;

use crate::stability::{Grid, FPS};
use crate::tip_moment;
use crate::{BenchError, BenchReport, Outcome, REFERENCE_FACTOR};

/// Largest segment strain the rod's projection may leave before the bench calls it constraint
/// drift (the bound `tests/tests/rod_collision_head_turning.rs` holds the rod to: below 10⁻⁴).
pub const ROD_STRAIN_LIMIT: f64 = 1e-4;

/// Energy gained against the truth, as a fraction of `Σ m g L`, beyond which a run that
/// finished is flagged as near-unstable.
pub const ENERGY_GAIN_LIMIT: f64 = 0.5;

/// The notes column of a finished run: the rod's projection figures, and an energy gain that
/// betrays a run at the edge of stability.
fn notes(projection: Option<&ProjectionReport>, energy_drift: Option<f64>) -> String {
    let mut note = projection.map_or(String::new(), projection_note);
    if energy_drift.is_some_and(|e| e > ENERGY_GAIN_LIMIT) {
        if !note.is_empty() {
            note += "; ";
        }
        let _ = write!(
            note,
            "**energy gain** above {ENERGY_GAIN_LIMIT} m g L: at the edge of stability"
        );
    }
    note
}

/// The rod's projection figures in words: mean and most iterations, residual, strain, and where
/// it failed.
fn projection_note(p: &ProjectionReport) -> String {
    let mut note = format!(
        "{:.1} it (max {}), residual {}, strain {}",
        p.mean_iterations(),
        p.max_iterations,
        sci(p.residual),
        sci(p.max_strain)
    );
    if p.unconverged > 0 {
        let _ = write!(
            note,
            "; **not converged** in {} of {} projections",
            p.unconverged, p.projections
        );
    }
    if p.max_strain > ROD_STRAIN_LIMIT {
        let _ = write!(
            note,
            "; **constraint drift** (strain > {ROD_STRAIN_LIMIT:.0e})"
        );
    }
    note
}

/// File names written into the output directory.
pub const FILES: [&str; 5] = [
    "pareto.png",
    "stability_map.png",
    "bench.md",
    "bench.json",
    "segments.png",
];

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
    charts::segments(report, &out.join(FILES[4]))?;
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
        "\n## Methods\n\nWhat each runs on the head case (as `MassSpringSolver::components` reports it):\n"
    );
    for (name, components) in &r.methods {
        let _ = writeln!(s, "- **{name}**: {components}");
    }
    let _ = writeln!(
        s,
        "\nEvery hair case is made of one physical hair (E = {} GPa, ρ = {} kg/m³, r = {} µm; \
         see `bench/src/physical.rs`): masses `μ l`, bending `EI/l³` for the mass-spring \
         model and `E` with a round section for the rod; **soft** springs are {:.2e} of the \
         physical `EA/l` (the default scene's 40 N/m on its wisp), **physical springs** are \
         `EA/l`. The rod's projection iteration limit is its own axis (one series per limit); \
         its truth uses {} iterations. The strips (seed 000) run only on the head-strips case, \
         beside the default mass-spring method on the same edge strands.",
        crate::physical::YOUNGS_MODULUS / 1e9,
        crate::physical::DENSITY,
        crate::physical::RADIUS * 1e6,
        crate::physical::soft_fraction(),
        crate::methods::Rod::REFERENCE_ITERATIONS
    );
    if !r.not_run.is_empty() {
        let _ = writeln!(s, "\n### Not run\n");
        let _ = writeln!(s, "| case | method | why |\n|---|---|---|");
        for n in &r.not_run {
            let _ = writeln!(s, "| {} | {} | {} |", n.case, n.method, n.reason);
        }
    }
    let _ = writeln!(
        s,
        "\n## Truths\n\nEvery method is measured against one **truth** per case: the analytic \
         answer where there is one, otherwise seed 002's rod with {} projection iterations on the \
         case's strands at twice the segments on the cantilever, curly and drape cases (the same \
         hair built finer) and on the head (refined on smooth curves through its points), with \
         its segments whole on the head strips (`bench/src/truth.rs`), at (at least) \
         {REFERENCE_FACTOR}× the finest substep count charted and within half its stability \
         bound. It counts as **converged** when halving its substep (time) and halving its \
         segments again (space) each change it (position RMS at the case's points) by less than \
         the smallest error charted against it.\n",
        crate::methods::Rod::REFERENCE_ITERATIONS
    );
    let _ = writeln!(
        s,
        "| case | truth | substeps/frame | change, substep halved (m) | change, segments halved again (m) | smallest error charted (m) | converged |"
    );
    let _ = writeln!(s, "|---|---|---:|---:|---:|---:|---|");
    for c in &r.truths {
        let analytic = c.substeps == 0;
        let dash = |x: f64| if analytic { "—".to_string() } else { sci(x) };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} |",
            c.case,
            c.truth,
            if analytic {
                "—".into()
            } else {
                c.substeps.to_string()
            },
            dash(c.time_change),
            dash(c.space_change),
            sci(c.smallest_error),
            if c.converged { "yes" } else { "**no**" }
        );
    }
    let _ = writeln!(
        s,
        "\n## Runs\n\nAgainst the case's truth (`hairsys::accuracy`): position error, RMS of \
         `|x − x_true|` over free points and sample frames (on chain-rest: the shape drift at \
         rest); tip error, RMS of the tips' distance (silhouette); length error, largest \
         `|L/L_rest − 1|` of a strand's length; curl kept, mean curvature at the last sample over \
         the truth's (— where the truth is straight). \
         Stretch: largest segment `len/rest − 1`. Energy drift: `(E(T) − E_true(T)) / Σ m g L` \
         (— where the truth has no comparable energy). \
         Penetration: deepest point centre inside the head. `auto` marks `substeps = \"auto\"`. \
         µs/frame/hair: cost per frame per hair the simulated strands stand for (head cases). \
         Notes: for the rod, mean (and most) iterations per projection, largest residual, largest \
         segment strain; a rod run whose projection stops at its limit, or leaves a strain above \
         {ROD_STRAIN_LIMIT:.0e}, says so; so does a run that ends with more than \
         {ENERGY_GAIN_LIMIT} m g L above the truth's energy. A failed run gives its cause.\n"
    );
    let _ = writeln!(
        s,
        "| case | method | substeps/frame | dt (s) | ms/frame | M point-substeps/s | position error (m) | tip error (m) | length error (%) | curl kept | max stretch (%) | energy drift | max penetration (mm) | µs/frame/hair | notes |"
    );
    let _ = writeln!(
        s,
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"
    );
    for run in &r.runs {
        let substeps = if run.auto {
            format!("{} (auto)", run.substeps)
        } else {
            run.substeps.to_string()
        };
        match &run.outcome {
            Outcome::Stable {
                cost,
                errors,
                projection,
            } => {
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | {} | {:.3} | {:.1} | {} | {} | {:.3} | {} | {:.3} | {} | {:.2} | {} | {} |",
                    run.case,
                    run.method,
                    substeps,
                    sci(run.dt),
                    cost.ms_per_frame,
                    cost.point_substeps_per_s / 1e6,
                    sci(errors.position_rms),
                    sci(errors.tip_rms),
                    100.0 * errors.length_error,
                    errors.curl_kept.map_or("—".into(), |c| format!("{c:.3}")),
                    100.0 * errors.max_stretch,
                    errors.energy_drift.map_or("—".into(), sci),
                    1e3 * errors.max_penetration,
                    cost.us_per_represented_hair
                        .map_or(String::new(), |us| format!("{us:.3}")),
                    notes(projection.as_ref(), errors.energy_drift),
                );
            }
            Outcome::Unstable { message } => {
                let cause: String = message.chars().take(140).collect();
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | {} | unstable | | | | | | | | | | fails: {} |",
                    run.case,
                    run.method,
                    substeps,
                    sci(run.dt),
                    cause.replace('|', "/")
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
        let default = |run: &&crate::Run| &run.case == case && run.method == "semi-implicit Euler";
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
    plan_table(&mut s, r);
    strips_table(&mut s, r);
    tip_moment_table(&mut s, r);
    segments_table(&mut s, r);
    let _ = writeln!(
        s,
        "\n## Stability\n\nProbe: 16 segments of 1 cm, 10 mg per point, no bending, released \
         horizontally under gravity, {} frames at {FPS} fps. Predicted bound `dt < 2/ω`, \
         `ω² = 4 (k_stretch + 4 k_bend)/m_min`; for the rod (whose stretching is a constraint) the \
         rows set its stiffest bending to the same frequency, `E I₂ = k l³/8`, and its bound is \
         `RodSolver::dt_max`, `ω² = 32 E I₂/(m_min l³)`; observed: the longest substep from \
         which every shorter one was stable.\n",
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

/// Where `hairsys plan` lands on the head case: its choice for each tolerance, its own error
/// and the truth's.
fn plan_table(s: &mut String, r: &BenchReport) {
    if r.plan.is_empty() {
        return;
    }
    let _ = writeln!(
        s,
        "\n## Where `hairsys plan` lands\n\n`hairsys::plan` on the head case's scene over its \
         whole frame range, for each tolerance: the plan measures its candidates against its own \
         reference (the inextensible mass-spring model at twice the bound's substeps, on probe \
         patches of the groom) and picks the cheapest within the tolerance; the bench runs that \
         choice on the whole case against the case's truth (the converged rod). The chart marks \
         each choice on the head panel (diamond, labelled with the tolerance).\n"
    );
    let _ = writeln!(
        s,
        "| case | tolerance (mm) | chosen | bench method | substeps/frame | plan's error (m, worst frame) | plan's error (m, RMS) | error vs truth (m) | tip error vs truth (m) | ms/frame | plan CPU (s) | note |"
    );
    let _ = writeln!(
        s,
        "|---|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---|"
    );
    let opt = |x: Option<f64>| x.map_or("—".to_string(), sci);
    for p in &r.plan {
        let _ = writeln!(
            s,
            "| {} | {:.1} | {} | {} | {} | {} | {} | {} | {} | {} | {:.2} | {} |",
            p.case,
            p.tolerance * 1e3,
            p.chosen.as_deref().unwrap_or("none"),
            p.method.as_deref().unwrap_or("—"),
            p.substeps,
            sci(p.plan_error),
            sci(p.plan_error_rms),
            opt(p.truth_error),
            opt(p.truth_tip_error),
            p.ms_per_frame
                .map_or("—".to_string(), |m| format!("{m:.3}")),
            p.plan_seconds,
            p.note
        );
    }
}

/// Cost per represented hair of the strips against the mass-spring model on the head cases.
fn strips_table(s: &mut String, r: &BenchReport) {
    let _ = writeln!(
        s,
        "\n## Strips: cost per represented hair\n\nThe strip model (seed 000) on the head-strips \
         case against the default mass-spring method on the same edge strands and on the head \
         case's hair (one strand per hair). Error: the edge strands against the rod truth on the \
         same strands at the sample frames.\n"
    );
    let _ = writeln!(
        s,
        "| case | method | substeps/frame | ms/frame | µs/frame/hair | represented hair-frames/s | edge error (m) |"
    );
    let _ = writeln!(s, "|---|---|---:|---:|---:|---:|---:|");
    for run in r.runs.iter().filter(|x| {
        (x.case == "head-strips" || (x.case == "head" && x.method == "semi-implicit Euler"))
            && !x.auto
    }) {
        if let Some((cost, errors)) = run.stable() {
            let us = cost.us_per_represented_hair.unwrap_or(f64::NAN);
            let _ = writeln!(
                s,
                "| {} | {} | {} | {:.3} | {:.3} | {} | {} |",
                run.case,
                run.method,
                run.substeps,
                cost.ms_per_frame,
                us,
                sci(1e6 / us),
                sci(errors.position_rms)
            );
        }
    }
}

/// The rod's cantilever under a tip moment against the elastica.
fn tip_moment_table(s: &mut String, r: &BenchReport) {
    let _ = writeln!(
        s,
        "\n## Rod: cantilever under a tip moment (the elastica)\n\nA clamped 0.4 m rod (20 \
         segments, EI = 10⁻³ N m², round) under a tip moment M, relaxed to rest by air drag over \
         2 s (see `bench/src/tip_moment.rs`). Analytic: the tip turns by t = ML/EI and lies \
         at u = L(sin t/t − 1), v = (L/t)(1 − cos t). Error: largest node distance from the arc \
         over L. The predicted bound 2/ω is {} s. The mass-spring model has no tip-moment input, \
         so it is not measured here.\n",
        sci(tip_moment::bound())
    );
    let _ = writeln!(
        s,
        "| t = ML/EI (rad) | analytic u, v (m) | iterations | dt / bound | tip turn (rad) | tip u (m) | tip v (m) | error / L | max strain | residual | unconverged substeps | µs/substep | status |"
    );
    let _ = writeln!(
        s,
        "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"
    );
    let opt = |x: Option<f64>| x.map_or(String::new(), sci);
    for t in &r.tip_moment {
        let (u, v) = tip_moment::analytic_tip(t.rotation);
        let _ = writeln!(
            s,
            "| {} | {}, {} | {} | {:.3} | {} | {} | {} | {} | {} | {} | {} of {} | {:.1} | {} |",
            t.rotation,
            sci(u),
            sci(v),
            t.iterations,
            t.dt_over_bound,
            t.tip_angle.map_or(String::new(), |a| format!("{a:.4}")),
            opt(t.tip_u),
            opt(t.tip_v),
            opt(t.error_over_length),
            opt(t.max_strain),
            sci(t.residual),
            t.unconverged,
            t.substeps,
            t.us_per_substep,
            t.status
        );
    }
}

/// The segments axis: per case, one row per method, one column per segment count.
fn segments_table(s: &mut String, r: &BenchReport) {
    if r.segments.is_empty() {
        return;
    }
    let _ = writeln!(
        s,
        "\n## Segments per strand\n\n![error against segments](segments.png)\n\nThe same \
         physical hair cut into 4 … 64 segments, every method at its own `auto` substeps, \
         against the case's truth at the case's points (equal fractions of the rest arc length; \
         see `bench/src/segments.rs`). Each cell: position RMS error (m), ms/frame and \
         substeps/frame chosen; on the curly case the curl kept, on the drape the deepest point \
         inside the sphere (m). Counts finer than the truth's \
         own segments cannot show errors below the truth's change with its segments doubled \
         (Truths table).\n"
    );
    let mut cases: Vec<&str> = Vec::new();
    for run in &r.segments {
        if !cases.contains(&run.case.as_str()) {
            cases.push(&run.case);
        }
    }
    for case in cases {
        let runs: Vec<_> = r.segments.iter().filter(|x| x.case == case).collect();
        let mut counts: Vec<usize> = runs.iter().map(|x| x.segments).collect();
        counts.sort_unstable();
        counts.dedup();
        let mut methods: Vec<&str> = Vec::new();
        for run in &runs {
            if !methods.contains(&run.method.as_str()) {
                methods.push(&run.method);
            }
        }
        let truth = r.truths.iter().find(|t| t.case == case);
        let _ = write!(s, "\n**{case}**");
        if let Some(t) = truth {
            let _ = write!(
                s,
                " (truth: {} segments per case segment; its change with segments doubled {} m",
                t.space_factor,
                sci(t.space_change)
            );
            if t.penetration > 0.0 || case == crate::drape::NAME {
                let _ = write!(
                    s,
                    "; its deepest point inside the sphere {} m",
                    sci(t.penetration)
                );
            }
            let _ = write!(s, ")");
        }
        let _ = writeln!(s, "\n");
        let header: Vec<String> = counts.iter().map(|n| format!("{n} segments")).collect();
        let _ = writeln!(s, "| method | {} |", header.join(" | "));
        let _ = writeln!(s, "|---|{}", "---|".repeat(counts.len()));
        for m in methods {
            let cells: Vec<String> = counts
                .iter()
                .map(|&n| {
                    let Some(run) = runs.iter().find(|x| x.method == m && x.segments == n) else {
                        return String::new();
                    };
                    match &run.outcome {
                        Outcome::Stable { cost, errors, .. } => {
                            let mut cell = format!(
                                "{} · {:.3} ms · {}",
                                sci(errors.position_rms),
                                cost.ms_per_frame,
                                run.substeps
                            );
                            if let Some(c) = errors.curl_kept {
                                let _ = write!(cell, " · curl {c:.2}");
                            }
                            if case == crate::drape::NAME {
                                let _ =
                                    write!(cell, " · in {}", sci(errors.max_penetration as f64));
                            }
                            cell
                        }
                        Outcome::Unstable { .. } => "unstable".into(),
                    }
                })
                .collect();
            let _ = writeln!(s, "| {m} | {} |", cells.join(" | "));
        }
    }
}
