//! The accuracy study on the shipped default scene (and the parity scene with its collider):
//! runs through a `Session` timed frame by frame, their error against a reference run and their
//! stretch. The studies in `bench/tests/implicit_euler_default_scene.rs` and
//! `bench/tests/xpbd_default_scene.rs` run it.

use std::time::{Duration, Instant};

use hairsys::scene::integrator::IntegratorChoice;
use hairsys::scene::{SceneFile, DEFAULT_SCENE};

use hairsys::Session;
use nalgebra::Vector3;

const PARITY_COLLIDE: &str = include_str!("../../scenes/parity_collide.toml");

/// Frames each run steps: 24 (the study's first table), or `STUDY_FRAMES` (up to the scene's 48).
pub fn frame_count() -> usize {
    std::env::var("STUDY_FRAMES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(24)
}

/// One run of the study: its frames' positions, stretches and cost.
pub struct Run {
    /// Largest stretch any frame reported.
    pub max_stretch: f32,
    /// What ran.
    pub label: String,
    /// Wall time per frame, ms.
    pub ms_per_frame: f64,
    /// The strand phase alone (force substeps, solve, contact response), ms/frame.
    pub strands_ms: f64,
    /// Positions of every frame, m.
    pub frames: Vec<Vec<[f32; 3]>>,
    /// `|len/rest − 1|` of every segment of every frame.
    pub stretch: Vec<f32>,
}

/// The shipped default scene on `integrator` at `substeps` (a TOML value), with the
/// inextensibility projection when `inextensible`.
pub fn scene(integrator: &str, substeps: &str, inextensible: bool) -> SceneFile {
    let mut text = DEFAULT_SCENE.replace("substeps = \"auto\"", &format!("substeps = {substeps}"));
    if inextensible {
        text = text.replace("# inextensibility = true", "inextensibility = true");
    }
    let mut file = SceneFile::parse(&text, "default (the study's scene)", ".".into()).unwrap();
    file.scene.solver.integrator = named(integrator);
    file
}

/// `file` with its stretch springs set to `STUDY_STRETCH` N/m when that variable is set (the
/// implicit integrators' runs: the explicit reference could not take stiffer springs at its
/// substep), else unchanged. Returns the label suffix naming the stiffness.
pub fn stiffened(file: &mut SceneFile) -> String {
    match std::env::var("STUDY_STRETCH")
        .ok()
        .and_then(|v| v.parse::<f32>().ok())
    {
        Some(k) => {
            file.scene.physics.stretch_stiffness = k;
            format!(", stretch {k} N/m")
        }
        None => String::new(),
    }
}

/// The integrator spelled `word` in a scene file.
fn named(word: &str) -> IntegratorChoice {
    word.parse().unwrap()
}
/// Steps `scene` for [`frame_count`] frames through a `Session`, timing each step.
pub fn run(label: &str, scene: &SceneFile) -> Run {
    let mut session = Session::from_scene(scene).unwrap();
    let offsets = session.strand_offsets().to_vec();
    let mut spent = Duration::ZERO;
    let mut strand_time = Duration::ZERO;
    let mut frames = Vec::new();
    let mut stretch = Vec::new();
    let mut max_stretch = 0.0f32;
    let rest: Vec<f32> = session.strands().rest_lengths().to_vec();
    for _ in 0..frame_count() {
        let t = Instant::now();
        let report = session.step().unwrap();
        spent += t.elapsed();
        strand_time += report.times.strands;
        max_stretch = max_stretch.max(report.max_stretch);
        let x = session.positions().to_vec();
        let mut seg = 0;
        for s in 0..offsets.len() - 1 {
            for i in offsets[s] as usize..offsets[s + 1] as usize - 1 {
                let d: f32 = (0..3).map(|c| (x[i + 1][c] - x[i][c]).powi(2)).sum();
                stretch.push((d.sqrt() / rest[seg] - 1.0).abs());
                seg += 1;
            }
        }
        frames.push(x);
    }
    let report = Run {
        max_stretch,
        label: label.into(),
        ms_per_frame: spent.as_secs_f64() * 1e3 / frames.len() as f64,
        strands_ms: strand_time.as_secs_f64() * 1e3 / frames.len() as f64,
        frames,
        stretch,
    };
    eprintln!(
        "  ran {label}: {:.1} ms/frame ({:.1} in the strand phase)",
        report.ms_per_frame, report.strands_ms
    );
    report
}

/// Distance of each of `a`'s points from `b`'s same point, per frame, m: their tail, beside
/// the RMS per frame ([`rms_per_frame`]), is what an RMS hides, a few strands going their own
/// way.
pub fn point_distances(a: &Run, b: &Run) -> Vec<Vec<f64>> {
    a.frames
        .iter()
        .zip(&b.frames)
        .map(|(x, y)| {
            x.iter()
                .zip(y)
                .map(|(p, q)| {
                    (0..3)
                        .map(|c| ((p[c] - q[c]) as f64).powi(2))
                        .sum::<f64>()
                        .sqrt()
                })
                .collect()
        })
        .collect()
}

/// RMS distance of each frame of `a` from the same frame of `b` over every point, m: the
/// library's measure ([`hairsys::accuracy::position_rms`]) with no point left out.
pub fn rms_per_frame(a: &Run, b: &Run) -> Vec<f64> {
    a.frames
        .iter()
        .zip(&b.frames)
        .map(|(x, y)| {
            let x: Vec<_> = x.iter().map(|p| Vector3::from(*p)).collect();
            let y: Vec<_> = y.iter().map(|p| Vector3::from(*p)).collect();
            hairsys::accuracy::position_rms(&x, &y, &vec![1.0; x.len()])
        })
        .collect()
}

/// The 99th percentile of `values`.
pub fn p99(values: &[f32]) -> f32 {
    let mut v = values.to_vec();
    v.sort_by(f32::total_cmp);
    quantile(&v, 0.99)
}

/// The `q` quantile (nearest rank below) of `sorted`, sorted ascending.
pub fn quantile<T: Copy>(sorted: &[T], q: f64) -> T {
    sorted[(q * (sorted.len() - 1) as f64) as usize]
}

/// Substep counts from the environment variable `var` (comma-separated), else `default`.
pub fn counts(var: &str, default: &str) -> Vec<u32> {
    std::env::var(var)
        .unwrap_or_else(|_| default.into())
        .split(',')
        .map(|s| s.trim().parse().unwrap())
        .collect()
}

/// Prints the study's table of `runs` against `reference` (Markdown).
pub fn table(runs: &[Run], reference: &Run) {
    println!(
        "| method | ms/frame | strand phase ms/frame | RMS error, min–max over frames (mm) | RMS \
         error, all frames (mm) | p99 / p99.9 / max distance (mm) | p99 stretch (%) |"
    );
    println!("|---|---|---|---|---|---|---|");
    for r in runs {
        let distances = point_distances(r, reference);
        let e = rms_per_frame(r, reference);
        let all = (e.iter().map(|x| x * x).sum::<f64>() / e.len() as f64).sqrt();
        let (lo, hi) = e
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
        let mut d: Vec<f64> = distances.into_iter().flatten().collect();
        d.sort_by(f64::total_cmp);
        println!(
            "| {} | {:.1} | {:.1} | {:.2}–{:.2} | {:.2} | {:.2} / {:.2} / {:.1} | {:.3} |",
            r.label,
            r.ms_per_frame,
            r.strands_ms,
            lo * 1e3,
            hi * 1e3,
            all * 1e3,
            quantile(&d, 0.99) * 1e3,
            quantile(&d, 0.999) * 1e3,
            d.last().copied().unwrap_or(0.0) * 1e3,
            100.0 * p99(&r.stretch)
        );
    }
    println!(
        "reference: {:.1} ms/frame, p99 stretch {:.3} %",
        reference.ms_per_frame,
        100.0 * p99(&reference.stretch)
    );
}

/// The parity scene with its head mesh as collider on `integrator` at `substeps`.
pub fn parity(integrator: &str, substeps: &str) -> SceneFile {
    parity_file(integrator, substeps, false)
}

/// The parity scene with its head mesh as collider on `integrator` at `substeps`, with the
/// inextensibility projection when `inextensible` (the reference of [`parity`]'s runs).
pub fn parity_file(integrator: &str, substeps: &str, inextensible: bool) -> SceneFile {
    let mut text = PARITY_COLLIDE
        .lines()
        .map(|line| match line.split_whitespace().next() {
            Some("substeps") => format!("substeps = {substeps}"),
            _ => line.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n");
    if inextensible {
        text = text.replace("max_strain = ", "inextensibility = true\nmax_strain = ");
    }
    let mut file = SceneFile::parse(
        &text,
        "parity_collide (the study's parity scene)",
        "scenes".into(),
    )
    .unwrap();
    file.scene.solver.integrator = named(integrator);
    file
}
