//! The quality report of a run as text lines for a terminal (`hairsys preview --report`): one
//! line per measure, in the units a TD reads (mm, %, degrees, m/s).

use hair_core::QualityReport;
use hairsys::output::quality::RunQuality;

/// The report as lines: penetration, strain, hairpins, velocity mismatch over the run, then the
/// drift from the groom at the first stepped frame and at the last frame.
pub fn describe(q: &RunQuality) -> String {
    let r = &q.run;
    let mut lines = vec![format!(
        "quality over {} stepped frame(s), {} point-frames:",
        r.frames, r.points
    )];
    lines.push(match &r.penetration {
        Some(p) => format!(
            "  inside colliders  {:.3} % of points deeper than {:.2} mm (worst frame {:.3} %), deepest {:.2} mm",
            p.inside_fraction * 100.0,
            p.tolerance * 1e3,
            p.worst_frame_fraction * 100.0,
            p.deepest * 1e3
        ),
        None => "  inside colliders  (no colliders)".into(),
    });
    lines.push(format!(
        "  stretch           p50 {:.2} %, p99 {:.2} %, max {:.2} %",
        r.strain.stretch.p50() * 100.0,
        r.strain.stretch.p99() * 100.0,
        r.strain.stretch.max() * 100.0
    ));
    lines.push(format!(
        "  compression       p50 {:.2} %, p99 {:.2} %, max {:.2} %",
        r.strain.compression.p50() * 100.0,
        r.strain.compression.p99() * 100.0,
        r.strain.compression.max() * 100.0
    ));
    lines.push(format!(
        "  hairpins          {} point-frame(s) turning > 90° (worst frame {}), largest turn {:.0}°",
        r.hairpins.count, r.hairpins.worst_frame, r.hairpins.max_turn_deg
    ));
    if let Some(v) = &r.velocity_mismatch {
        lines.push(format!(
            "  velocity mismatch p50 {:.3} m/s, p99 {:.3} m/s, max {:.3} m/s",
            v.p50(),
            v.p99(),
            v.max()
        ));
    }
    lines.push(drift_line("drift, first step", &q.first_step));
    lines.push(drift_line("drift, last frame", &q.last));
    lines.join("\n")
}

fn drift_line(name: &str, r: &QualityReport) -> String {
    match &r.drift {
        Some(d) => format!(
            "  {name:<17} RMS {:.1} mm, max {:.1} mm; tips RMS {:.1} mm, max {:.1} mm",
            d.rms * 1e3,
            d.max * 1e3,
            d.tip_rms * 1e3,
            d.tip_max * 1e3
        ),
        None => format!("  {name:<17} (not measured)"),
    }
}
