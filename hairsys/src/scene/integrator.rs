//! `[solver] integrator`: a named time integrator, or `"auto"` (the default), which picks the
//! cheaper of semi-implicit Euler and BDF2 for the scene's strands.
//!
//! # The rule
//!
//! Both integrators meet the same accuracy where `"auto"` uses them (on the default scene, RMS
//! against the inextensible reference at 512 substeps over the whole 48-frame shot: semi-implicit
//! Euler at its stability bound 0.69 mm, BDF2 at its accuracy limit of 1/168 s 1.36 mm, both
//! under the 1.5 mm target with p99 stretch under 1 %; implicit Euler at 1/384 s, 1.21 mm over
//! the first 24 frames, is 1.86 mm over all 48). What differs is the cost:
//!
//! - semi-implicit Euler needs the substeps its **stability bound** asks for
//!   ([`hair_core::StabilityBound`]): few on long soft segments (the parity scene: 19 per frame),
//!   many where short segments carry stiff springs (the default scene 165, the character 434);
//! - BDF2 needs the substeps its **accuracy limit** asks for (7 per frame at 24 fps), whatever
//!   the stiffness, but each costs [`IMPLICIT_SUBSTEP_COST`] explicit substeps (a banded solve
//!   per strand instead of a force sweep). Implicit Euler does not serve here: it needs 16
//!   substeps per frame for a slightly larger error, with 5–13× the artificial damping of a
//!   swing.
//!
//! So `"auto"` takes BDF2 when the stability bound's substeps cost more than the accuracy
//! limit's BDF2 ones, and semi-implicit Euler otherwise (ties go to semi-implicit Euler, the
//! more accurate of the two per substep). Where a rest joint of the groom turns by more than
//! [`MAX_IMPLICIT_REST_TURN`], BDF2's substep is [`SHARP_JOINT_BDF2_DT`] instead (32 per frame at
//! 24 fps), and the cost comparison uses that count. Those grooms take bending's Gauss–Newton
//! Hessian (`hair_core::integrate` module `implicit`, above 30°), with which BDF2 holds them, but
//! only at the finer step:
//! - on the bench's curly hair (every joint 46°) BDF2 gains energy at 8 substeps per frame
//!   (stretch 73 %) and 16 (14 %), and holds the converged run's 0.14 % from 32 (0.16 %);
//! - on Sintel (5 of 29,090 joints at 71–83°, next to her roots) BDF2 at 8 substeps stays 0.68
//!   mm RMS from the semi-implicit run at its bound (2,626 substeps per frame) but leaves 44
//!   point-frames more than 0.1 mm inside the bust (deepest 1.45 mm; the semi-implicit run: 3,
//!   0.51 mm); at 32: 0.16 mm RMS, 3 point-frames (0.28 mm), no hairpins, 17× faster
//!   (84.6 against 1,418 ms per frame). The finer step is for her whole groom, not only the
//!   strands with a sharp joint: given only to the solver's groups holding one, the rest at 7,
//!   the strand phase falls 3× but 599 point-frames of gently bent strands end more than 1 cm
//!   from the converged run (none at 32 everywhere), up to 33 mm, and the deepest point goes to
//!   1.16 mm.
//!
//! With the small-angle Hessian, Sintel's five sharp joints fold into hairpins under implicit
//! Euler (29 point-frames at 16 substeps, up to 150°; still 26 at 64). The default, wind, gust,
//! collision and character grooms turn at most 27–32° per joint and never take this rule. A
//! fixed substep count on a sharply bent groom keeps semi-implicit Euler where it is stable:
//! the count was chosen by hand. How the rule for such grooms came to be:
//! `docs/design/auto-integrator.md`.
//!
//! With a fixed substep count it takes semi-implicit Euler where that count is within the
//! stability bound and BDF2 where it is not (stable far past the bound). Only the
//! mass-spring model has a choice: the rod and the strips keep their own schemes.
//!
//! **Contacts.** The implicit integrators apply the contact response after each substep's solve,
//! as the explicit kernel does, at 7 substeps a frame instead of 150–430. The springs then pull a
//! pushed-out point back towards its neighbours for a whole substep before the next response,
//! but on the shipped scenes that stays within the look bounds
//! (`tests/tests/shipped_scenes_look.rs`). Within the steps, BDF2 at 7 substeps leaves points
//! deeper than semi-implicit Euler at its bound (deepest point inside and point-frames more than
//! 0.1 mm inside): the collision scene's moving ball 0.151 mm, 31 (0.113 mm, 9); the keyed gust
//! swept into the still head 0.138 mm, 18 (0.128 mm, 4); the character's deforming body none
//! (none), p99 stretch 0.49 %. The solver's frame-end check then moves every point the
//! substeps' contact model left deeper than 25 µm back, within the strain limit
//! (`hair_core::contacts`), so no cached frame of these scenes has a point beyond 0.1 mm
//! (BENCHMARKS.md, "Shipped scenes"). The scalp, rigid or deforming, does not count:
//! the hair is rooted on it and moves with it. Animated guides do not count either.
//!
//! What BDF2's few substeps cannot follow is a collider that crosses a large part of its own
//! size in one: a 0.1 m ball at 24 m/s through hanging hair (1.4 of its radius per substep at
//! 8 substeps per frame) blows up without a strain limit and with one leaves points 5 mm inside,
//! while the collision scene's 0.06 m ball (0.29 of its radius) stays within the bounds. So
//! `"auto"` keeps semi-implicit Euler where a `[[colliders]]` surface moves more than
//! [`MAX_BDF2_CROSSING`] of its bounding radius in one BDF2 substep ([`ContactLoad`]: the
//! fastest point of its rigid motion plus the fastest vertex of its deformation), and where a
//! host moves colliders without saying how fast. The tried alternative, holding contacts inside
//! the banded solve, is recorded in `docs/design/held-contacts.md`.
//!
//! The choice is made once, when the scene is built, from the strands at rest (per-region
//! stiffness included), so a run and its resume take the same integrator.

use std::fmt;

use hair_core::{Integrator, SolverSettings, StabilityBound, StrandModel, StrandSet, Substeps};
use serde::de::{Deserializer, Error as _};
use serde::ser::Serializer;
use serde::{Deserialize, Serialize};

/// Strand-phase cost of one BDF2 substep in semi-implicit Euler substeps on the same strands, as
/// `"auto"` weighs it. Measured on a 2-core machine (`implicit_euler_default_scene`,
/// strand-phase ms per frame over substeps per frame), a BDF2 substep costs 2.2 on the default
/// scene (2.16–2.34 at 8–6 substeps per frame) and 2.4–2.8 on the parity scene with its collider
/// at 1–4 substeps per frame, 1.7 at 7 (strand phase 65.6 ms at 7 against 99.3 at the 18
/// semi-implicit substeps). The value is 3, above those: at 2.2 the scenes that would move to
/// BDF2 at 7 substeps per frame are those whose bound asks for 16–21 explicit ones, long soft
/// hair like the parity scene's, and there BDF2 at 7 buys its time with position error: 0.7×
/// the time at 1.05× the error against the converged reference (48.6 against 46.4 mm RMS over
/// the shot), so `"auto"` leaves such hair on the more accurate method. Whether so small an
/// error should still outweigh the time is open. Earlier measurements of this ratio (2.9 for
/// BDF2 and 2.0–3.4 for implicit Euler before the block solve): `docs/design/auto-integrator.md`.
pub const IMPLICIT_SUBSTEP_COST: f64 = 3.0;

/// Largest turn of a rest joint (rad) for which `"auto"` takes BDF2 at its accuracy limit's
/// step; sharper grooms take [`SHARP_JOINT_BDF2_DT`]. 45°, between the shipped grooms' 32° and
/// Sintel's 71–83° (module docs), where the curvature measure `2 tan(θ/2)` departs from the
/// angle by 5.5 %.
pub const MAX_IMPLICIT_REST_TURN: f64 = std::f64::consts::FRAC_PI_4;

/// BDF2's substep under `"auto"` substeps where a rest joint turns by more than
/// [`MAX_IMPLICIT_REST_TURN`], s: 1/768 s, 32 substeps per frame at 24 fps (module docs: the
/// coarsest step at which BDF2 holds the bench's curly hair and Sintel's bust).
pub const SHARP_JOINT_BDF2_DT: f64 = 1.0 / 768.0;

/// Substeps shorter than this (s) put BDF2 on sharply bent hair where it can flutter (module
/// docs of `hair_core::integrate` module `implicit`): on the bench's curly hair (46° joints) it
/// settles at 1/1536 s and gains energy, stretching 2–5 %, at 1/3072–1/12288 s.
/// 1/2048 s lies between; the window's short end moves with the physical damping, so every
/// shorter substep is warned of.
pub const BDF2_FLUTTER_DT: f64 = 1.0 / 2048.0;

/// Largest distance a collider's surface may move in one BDF2 substep for `"auto"` to take
/// BDF2, as a fraction of the collider's bounding radius (module docs): above the collision
/// scene's ball (0.29) and below a ball crossing hanging hair at 24 m/s (1.4).
pub const MAX_BDF2_CROSSING: f64 = 0.5;

/// How fast a scene's colliders move against their size, for `"auto"`'s contact condition
/// (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactLoad {
    /// Largest ratio over the colliders (the scalp's excluded) of the fastest speed of a point of
    /// its surface over the shot to its bounding radius, 1/s: in one substep of `dt` seconds the
    /// fastest collider crosses this times `dt` of its own size (0 without moving colliders).
    pub crossing_rate: f64,
    /// A host poses colliders frame by frame without saying how fast they move.
    pub unknown_collider_speed: bool,
}

impl ContactLoad {
    /// The load of colliders given as `(fastest surface speed m/s, bounding radius m)`; a
    /// collider of no size counts as crossing itself at any speed but 0.
    pub fn from_colliders(colliders: impl IntoIterator<Item = (f64, f64)>) -> Self {
        let crossing_rate = colliders
            .into_iter()
            .filter(|&(speed, _)| speed > 0.0)
            .map(|(speed, radius)| {
                if radius > 0.0 {
                    speed / radius
                } else {
                    f64::INFINITY
                }
            })
            .fold(0.0, f64::max);
        Self {
            crossing_rate,
            unknown_collider_speed: false,
        }
    }

    /// Why BDF2's few substeps of `dt` (s) cannot follow the colliders here, if they cannot.
    fn too_hard(&self, dt: f64) -> Option<String> {
        let crossing = self.crossing_rate * dt;
        if self.unknown_collider_speed {
            Some("colliders move as the host poses them, at a speed it did not give".into())
        } else if crossing > MAX_BDF2_CROSSING {
            Some(format!(
                "a collider's surface moves {:.0} % of its size in one BDF2 substep, more than \
                 {:.0} %",
                crossing * 100.0,
                MAX_BDF2_CROSSING * 100.0
            ))
        } else {
            None
        }
    }
}

/// Fastest speed of a point within `radius` (m) of the origin of a body moving by `pose(t)` over
/// frames `first..=last` (frame numbers), m/s: sampled at quarter frames, translation plus
/// rotation angle times `radius` per sample interval.
pub fn fastest_surface_speed(
    pose: impl Fn(f32) -> nalgebra::Isometry3<f32>,
    radius: f64,
    first: u32,
    last: u32,
    fps: f64,
) -> f64 {
    const PER_FRAME: u32 = 4;
    let interval = 1.0 / (fps * f64::from(PER_FRAME));
    let samples = (last.saturating_sub(first)) * PER_FRAME;
    (0..samples)
        .map(|k| {
            let t0 = first as f32 + k as f32 / PER_FRAME as f32;
            let t1 = first as f32 + (k + 1) as f32 / PER_FRAME as f32;
            let (a, b) = (pose(t0), pose(t1));
            let moved = f64::from((b.translation.vector - a.translation.vector).norm());
            let turned = f64::from(a.rotation.angle_to(&b.rotation));
            (moved + turned * radius) / interval
        })
        .fold(0.0, f64::max)
}

/// `[solver] integrator`: `"auto"` or a named integrator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum IntegratorChoice {
    /// The cheaper of semi-implicit Euler and BDF2 for the scene (module docs).
    #[default]
    Auto,
    /// This integrator, whatever it costs.
    Named(Integrator),
}

/// The integrator a scene runs, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct ResolvedIntegrator {
    /// The integrator the solver takes.
    pub integrator: Integrator,
    /// Whether `"auto"` chose it.
    pub auto: bool,
    /// Substeps per step semi-implicit Euler would take (the fixed count, or the stability
    /// bound's for `"auto"` substeps, on the groom before sag-free initialisation, which can
    /// move the bound by a fraction of a percent).
    pub explicit_substeps: u32,
    /// Substeps per step BDF2 would take (the fixed count, or its accuracy limit's, or the count
    /// of [`SHARP_JOINT_BDF2_DT`] on a sharply bent groom).
    pub implicit_substeps: u32,
    /// The fixed substep count the solver must be given instead of `"auto"`: BDF2's finer step
    /// on a sharply bent groom (`None`: the scene's substeps as written).
    pub substeps_override: Option<u32>,
    /// Largest turn of a rest joint over the strands, rad.
    pub max_rest_turn: f64,
    /// The rule that decided.
    pub rule: Rule,
    /// Where the scene named an implicit integrator at a substep it was measured not to hold
    /// on hair this sharply bent, what to expect and what to take instead
    /// ([`sharp_joint_warning`]).
    pub warning: Option<String>,
}

/// Which of `"auto"`'s rules (module docs) decided an integrator.
#[derive(Debug, Clone, PartialEq)]
pub enum Rule {
    /// The scene named the integrator.
    Named,
    /// The rod or the strips: the integrator is not used.
    OtherModel,
    /// The cost comparison alone.
    Cost,
    /// A rest joint turns more than [`MAX_IMPLICIT_REST_TURN`]: with `"auto"` substeps, BDF2 at
    /// [`SHARP_JOINT_BDF2_DT`] where that is cheaper; with a fixed count, semi-implicit Euler.
    SharpJoint,
    /// The cost asked for BDF2, but contact is too hard for it (why, in words).
    HardContact(String),
}

impl ResolvedIntegrator {
    /// Why `"auto"` chose what it chose, in words (empty for a named integrator).
    pub fn reason(&self) -> String {
        let explicit = self.explicit_substeps;
        let implicit = self.implicit_substeps;
        let fallback = format!("so semi-implicit Euler (about {explicit} substeps per step)");
        match &self.rule {
            Rule::Named | Rule::OtherModel => String::new(),
            Rule::HardContact(why) => {
                format!("{why}, which BDF2's few substeps do not follow, {fallback}")
            }
            Rule::Cost | Rule::SharpJoint if self.integrator == Integrator::Bdf2 => {
                let why = format!(
                    "semi-implicit Euler would need about {explicit} substeps per step for \
                     stability, more than {implicit} BDF2 substeps at {IMPLICIT_SUBSTEP_COST}× \
                     the cost"
                );
                if self.rule == Rule::SharpJoint {
                    format!(
                        "{why} (the finer BDF2 step a rest joint turning {:.0}° needs, beyond \
                         {:.0}°)",
                        self.max_rest_turn.to_degrees(),
                        MAX_IMPLICIT_REST_TURN.to_degrees()
                    )
                } else {
                    why
                }
            }
            Rule::SharpJoint => format!(
                "a rest joint turns {:.0}°, beyond {:.0}°, and the substep count is fixed, \
                 {fallback}",
                self.max_rest_turn.to_degrees(),
                MAX_IMPLICIT_REST_TURN.to_degrees()
            ),
            Rule::Cost => format!(
                "about {explicit} semi-implicit substeps per step are stable and cost no more \
                 than {implicit} BDF2 substeps at {IMPLICIT_SUBSTEP_COST}× the cost"
            ),
        }
    }
}

impl IntegratorChoice {
    /// The integrator for strands of `model` whose stability bound is `bound` and whose rest
    /// joints turn by at most `max_rest_turn` (rad, see [`max_rest_turn`]), under the contact
    /// load `contact`, stepped with `settings` (its `integrator` field is ignored; its substeps
    /// are the scene's).
    pub fn resolve(
        self,
        model: StrandModel,
        settings: &SolverSettings,
        bound: &StabilityBound,
        max_rest_turn: f64,
        contact: &ContactLoad,
    ) -> ResolvedIntegrator {
        let with = |integrator| {
            SolverSettings {
                integrator,
                ..*settings
            }
            .resolved_substeps(bound)
        };
        let explicit_substeps = with(Integrator::SemiImplicitEuler);
        let sharp = max_rest_turn > MAX_IMPLICIT_REST_TURN;
        // A sharply bent groom's BDF2 takes the finer step (module docs).
        let substeps_override = (sharp && settings.substeps == Substeps::Auto).then(|| {
            hair_core::integrate::substeps_within(settings.step_dt(), SHARP_JOINT_BDF2_DT)
        });
        let implicit_substeps = substeps_override.unwrap_or_else(|| with(Integrator::Bdf2));
        // BDF2 is the cheaper (or, at a fixed count, the only stable) of the two.
        let cheaper = match settings.substeps {
            Substeps::Auto => {
                f64::from(explicit_substeps) > IMPLICIT_SUBSTEP_COST * f64::from(implicit_substeps)
            }
            Substeps::Fixed(n) => n < bound.auto_substeps(settings.step_dt()),
        };
        let dt = settings.step_dt() / f64::from(implicit_substeps.max(1));
        let rule = match self {
            Self::Named(_) => Rule::Named,
            Self::Auto if model != StrandModel::MassSpring => Rule::OtherModel,
            Self::Auto if !cheaper => Rule::Cost,
            // A fixed count on a sharply bent groom: semi-implicit Euler (module docs).
            Self::Auto if sharp && substeps_override.is_none() => Rule::SharpJoint,
            Self::Auto => match contact.too_hard(dt) {
                Some(why) => Rule::HardContact(why),
                None if sharp => Rule::SharpJoint,
                None => Rule::Cost,
            },
        };
        // Past the fixed-count case, a sharp joint's rule is reached only where BDF2 is cheaper.
        let integrator = match (self, &rule) {
            (Self::Named(integrator), _) => integrator,
            (Self::Auto, Rule::Cost) if cheaper => Integrator::Bdf2,
            (Self::Auto, Rule::SharpJoint) if substeps_override.is_some() => Integrator::Bdf2,
            (Self::Auto, _) => Integrator::SemiImplicitEuler,
        };
        // The override only matters where BDF2 runs.
        let substeps_override = substeps_override.filter(|_| integrator == Integrator::Bdf2);
        // A named implicit integrator runs at whatever substep the scene gives it.
        let warning = match (self, integrator) {
            (Self::Named(_), Integrator::Bdf2 | Integrator::ImplicitEuler)
                if model == StrandModel::MassSpring && sharp =>
            {
                let substeps = substeps_override.unwrap_or_else(|| with(integrator));
                let dt = settings.step_dt() / f64::from(substeps.max(1));
                sharp_joint_warning(integrator, dt, max_rest_turn)
            }
            _ => None,
        };
        ResolvedIntegrator {
            integrator,
            auto: self == Self::Auto,
            explicit_substeps,
            implicit_substeps,
            substeps_override,
            max_rest_turn,
            rule,
            warning,
        }
    }
}

/// What a named implicit integrator at substep `dt` (s) risks on hair whose sharpest rest joint
/// turns by `turn` (rad, beyond [`MAX_IMPLICIT_REST_TURN`]), from the bench's curly hair (46°
/// joints): longer than [`SHARP_JOINT_BDF2_DT`] both implicit integrators stretch it 11–95 %
/// (1/384 s and longer; 0.2 % at 1/768 s); BDF2 shorter than [`BDF2_FLUTTER_DT`] flutters.
/// `None` where neither applies.
pub fn sharp_joint_warning(integrator: Integrator, dt: f64, turn: f64) -> Option<String> {
    let name = integrator_name(integrator);
    let bent = format!(
        "hair whose rest joints turn up to {:.0}° (beyond {:.0}°)",
        turn.to_degrees(),
        MAX_IMPLICIT_REST_TURN.to_degrees()
    );
    if dt > SHARP_JOINT_BDF2_DT * (1.0 + 1e-9) {
        Some(format!(
            "{name} at substeps of {dt:.2e} s may not hold {bent}: on the bench's curly hair \
             (46° joints) it stretched segments by 11–95 % at 1/384 s and longer and 0.2 % at \
             1/768 s; use substeps = \"auto\" (BDF2: 1/768 s) or a count giving at most 1/768 s"
        ))
    } else if integrator == Integrator::Bdf2 && dt < BDF2_FLUTTER_DT {
        Some(format!(
            "{name} at substeps of {dt:.2e} s can flutter on {bent}: on the bench's curly hair \
             (46° joints) it gained energy and stretched segments by 2–5 % at 1/3072–1/12288 s; \
             implicit-euler settles at every such substep, or use substeps = \"auto\" (1/768 s)"
        ))
    } else {
        None
    }
}

/// Largest angle between consecutive rest segments over `strands`, rad (0 for straight
/// strands; degenerate segments are skipped).
pub fn max_rest_turn(strands: &StrandSet) -> f64 {
    let rest = strands.rest_local();
    (0..strands.len())
        .flat_map(|s| {
            let points = &rest[strands.points(s)];
            points.windows(3).filter_map(|w| {
                let a = (w[1] - w[0]).cast::<f64>();
                let b = (w[2] - w[1]).cast::<f64>();
                let norms = a.norm() * b.norm();
                (norms > 0.0).then(|| (a.dot(&b) / norms).clamp(-1.0, 1.0).acos())
            })
        })
        .fold(0.0, f64::max)
}

/// The scene-file spelling of `integrator`.
pub fn integrator_name(integrator: Integrator) -> &'static str {
    match integrator {
        Integrator::SemiImplicitEuler => "semi-implicit-euler",
        Integrator::ExplicitEuler => "explicit-euler",
        Integrator::ImplicitEuler => "implicit-euler",
        Integrator::Bdf2 => "bdf2",
        Integrator::Xpbd => "xpbd",
    }
}

const NAMES: &str =
    "\"auto\", \"semi-implicit-euler\", \"implicit-euler\", \"bdf2\", \"xpbd\" or \"explicit-euler\"";

impl fmt::Display for IntegratorChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Auto => f.write_str("auto"),
            Self::Named(i) => f.write_str(integrator_name(*i)),
        }
    }
}

impl Serialize for IntegratorChoice {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}

/// A word that is neither `"auto"` nor an integrator's name.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown integrator {word:?}: use {NAMES}", NAMES = NAMES)]
pub struct UnknownIntegrator {
    /// The word given.
    pub word: String,
}

impl std::str::FromStr for IntegratorChoice {
    type Err = UnknownIntegrator;

    /// Parses the scene-file spelling: `"auto"` or an integrator's name.
    fn from_str(word: &str) -> Result<Self, UnknownIntegrator> {
        if word == "auto" {
            return Ok(Self::Auto);
        }
        [
            Integrator::SemiImplicitEuler,
            Integrator::ImplicitEuler,
            Integrator::Bdf2,
            Integrator::Xpbd,
            Integrator::ExplicitEuler,
        ]
        .into_iter()
        .find(|&i| integrator_name(i) == word)
        .map(Self::Named)
        .ok_or_else(|| UnknownIntegrator {
            word: word.to_string(),
        })
    }
}

impl<'de> Deserialize<'de> for IntegratorChoice {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        String::deserialize(deserializer)?
            .parse()
            .map_err(D::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bound(dt_max: f64) -> StabilityBound {
        StabilityBound {
            omega: 2.0 / dt_max,
            dt_max,
            stiffness: 1.0,
            min_mass: 1.0,
        }
    }

    fn settings(substeps: Substeps) -> SolverSettings {
        SolverSettings {
            substeps,
            ..SolverSettings::default()
        }
    }

    /// At 24 fps BDF2's accuracy limit asks for 7 substeps, so `"auto"` changes over where the
    /// stability bound asks for more than 21.
    #[test]
    fn auto_takes_bdf2_where_the_stability_bound_costs_more() {
        let step = 1.0 / 24.0;
        let s = settings(Substeps::Auto);
        let stiff = IntegratorChoice::Auto.resolve(
            StrandModel::MassSpring,
            &s,
            &bound(step / 165.0 / hair_core::integrate::stability::AUTO_SAFETY),
            0.5,
            &ContactLoad::default(),
        );
        assert_eq!(stiff.integrator, Integrator::Bdf2);
        assert_eq!((stiff.explicit_substeps, stiff.implicit_substeps), (165, 7));
        let soft = IntegratorChoice::Auto.resolve(
            StrandModel::MassSpring,
            &s,
            &bound(step / 12.0 / hair_core::integrate::stability::AUTO_SAFETY),
            0.5,
            &ContactLoad::default(),
        );
        assert_eq!(soft.integrator, Integrator::SemiImplicitEuler);
        assert_eq!(soft.explicit_substeps, 12);
        // 21 explicit substeps cost exactly 7 BDF2 ones: semi-implicit Euler.
        let tie = IntegratorChoice::Auto.resolve(
            StrandModel::MassSpring,
            &s,
            &bound(step / 21.0 / hair_core::integrate::stability::AUTO_SAFETY * 1.000001),
            0.5,
            &ContactLoad::default(),
        );
        assert_eq!(tie.explicit_substeps, 21);
        assert_eq!(tie.integrator, Integrator::SemiImplicitEuler);
    }

    /// A sharply pre-bent joint takes BDF2 at the finer step where that is still cheaper, and
    /// keeps semi-implicit Euler where it is not or where the substep count is fixed.
    #[test]
    fn auto_takes_bdf2_at_the_finer_step_where_a_rest_joint_turns_sharply() {
        let step = 1.0 / 24.0;
        let b = bound(step / 2626.0 / hair_core::integrate::stability::AUTO_SAFETY);
        let at = |turn_deg: f64, substeps: Substeps, b: &StabilityBound| {
            IntegratorChoice::Auto.resolve(
                StrandModel::MassSpring,
                &settings(substeps),
                b,
                turn_deg.to_radians(),
                &ContactLoad::default(),
            )
        };
        let gentle = at(32.0, Substeps::Auto, &b);
        assert_eq!(gentle.integrator, Integrator::Bdf2);
        assert_eq!(
            (gentle.implicit_substeps, gentle.substeps_override),
            (7, None)
        );
        // Sintel: 2,626 explicit substeps against 32 BDF2 ones.
        let sharp = at(83.0, Substeps::Auto, &b);
        assert_eq!(sharp.integrator, Integrator::Bdf2);
        assert_eq!(sharp.rule, Rule::SharpJoint);
        assert_eq!(
            (sharp.implicit_substeps, sharp.substeps_override),
            (32, Some(32))
        );
        assert!(sharp.reason().contains("83°"), "{}", sharp.reason());
        // 48 explicit substeps would take BDF2 at 7, but not at 32.
        let soft = bound(step / 48.0 / hair_core::integrate::stability::AUTO_SAFETY);
        assert_eq!(at(32.0, Substeps::Auto, &soft).integrator, Integrator::Bdf2);
        let sharp_soft = at(83.0, Substeps::Auto, &soft);
        assert_eq!(sharp_soft.integrator, Integrator::SemiImplicitEuler);
        assert_eq!(sharp_soft.substeps_override, None);
        // A fixed count below the stability bound: semi-implicit Euler as written.
        let fixed = at(83.0, Substeps::Fixed(40), &b);
        assert_eq!(fixed.integrator, Integrator::SemiImplicitEuler);
        assert_eq!(fixed.rule, Rule::SharpJoint);
        assert!(fixed.reason().contains("fixed"), "{}", fixed.reason());
    }

    /// A named implicit integrator on sharply bent hair is warned of where the bench's curly
    /// hair did not hold: longer substeps than 1/768 s, and BDF2 shorter than 1/2048 s; `"auto"`
    /// and straighter hair are not.
    #[test]
    fn named_implicit_integrators_are_warned_of_off_the_steps_sharp_hair_holds() {
        let b = bound(1.0 / 24.0 / 2626.0 / hair_core::integrate::stability::AUTO_SAFETY);
        let at = |choice: IntegratorChoice, turn_deg: f64, substeps: Substeps| {
            choice
                .resolve(
                    StrandModel::MassSpring,
                    &settings(substeps),
                    &b,
                    turn_deg.to_radians(),
                    &ContactLoad::default(),
                )
                .warning
        };
        let bdf2 = IntegratorChoice::Named(Integrator::Bdf2);
        let euler = IntegratorChoice::Named(Integrator::ImplicitEuler);
        // At 24 fps: 8 and 16 substeps per frame are too long, 32 and 64 hold, 128 flutters.
        for n in [8, 16] {
            let w = at(bdf2, 46.0, Substeps::Fixed(n)).expect("a warning");
            assert!(w.contains("1/768 s") && w.contains("46°"), "{w}");
            assert!(at(euler, 46.0, Substeps::Fixed(n)).is_some());
        }
        for n in [32, 64] {
            assert_eq!(at(bdf2, 46.0, Substeps::Fixed(n)), None, "{n}");
            assert_eq!(at(euler, 46.0, Substeps::Fixed(n)), None, "{n}");
        }
        let w = at(bdf2, 46.0, Substeps::Fixed(128)).expect("a warning");
        assert!(w.contains("flutter") && w.contains("implicit-euler"), "{w}");
        assert_eq!(at(euler, 46.0, Substeps::Fixed(128)), None);
        // "auto" substeps: BDF2 takes 1/768 s; implicit Euler its own 1/384 s, too long here.
        assert_eq!(at(bdf2, 46.0, Substeps::Auto), None);
        assert!(at(euler, 46.0, Substeps::Auto).is_some());
        // Straighter hair, "auto" integrators and explicit ones are not warned of.
        assert_eq!(at(bdf2, 32.0, Substeps::Fixed(8)), None);
        assert_eq!(at(IntegratorChoice::Auto, 83.0, Substeps::Fixed(8)), None);
        let explicit = IntegratorChoice::Named(Integrator::SemiImplicitEuler);
        assert_eq!(at(explicit, 83.0, Substeps::Fixed(8)), None);
    }

    #[test]
    fn max_rest_turn_is_the_sharpest_joint() {
        let mut strands = StrandSet::new();
        let (s, c) = 70f32.to_radians().sin_cos();
        let points = vec![
            nalgebra::Vector3::new(0.0, 0.0, 0.0),
            nalgebra::Vector3::new(0.0, 0.0, 0.01),
            nalgebra::Vector3::new(0.0, 0.0, 0.02),
            nalgebra::Vector3::new(0.01 * s, 0.0, 0.02 + 0.01 * c),
        ];
        let input = hair_core::StrandInput::uniform(
            hair_core::Anchor::Body(hair_core::RootFrame::at(nalgebra::Vector3::zeros())),
            points,
            0.001,
            0.0001,
            0.0,
            0.0,
        );
        strands.push(input).unwrap();
        assert!((max_rest_turn(&strands).to_degrees() - 70.0).abs() < 1e-3);
    }

    /// A collider crossing more than [`MAX_BDF2_CROSSING`] of its size in one BDF2 substep, or
    /// one a host moves at a speed it did not give, keeps semi-implicit Euler; slower ones take
    /// BDF2.
    #[test]
    fn auto_keeps_semi_implicit_euler_for_fast_colliders() {
        let step = 1.0 / 24.0;
        let b = bound(step / 165.0 / hair_core::integrate::stability::AUTO_SAFETY);
        let s = settings(Substeps::Auto);
        let at = |contact: ContactLoad| {
            IntegratorChoice::Auto.resolve(StrandModel::MassSpring, &s, &b, 0.3, &contact)
        };
        // 7 substeps of 1/168 s. A 0.06 m ball at 3 m/s crosses 30 % of its radius in one; at
        // 24 m/s 238 %; a 0.1 m ball at 8 m/s 48 %, at 9 m/s 54 %.
        for (speed, radius, bdf2) in [
            (3.0, 0.06, true),
            (24.0, 0.06, false),
            (8.0, 0.1, true),
            (9.0, 0.1, false),
            (0.0, 0.0, true),
            (0.1, 0.0, false),
        ] {
            let r = at(ContactLoad::from_colliders([(speed, radius), (0.0, 1.0)]));
            assert_eq!(
                r.integrator == Integrator::Bdf2,
                bdf2,
                "{speed} m/s, {radius} m: {}",
                r.reason()
            );
            if !bdf2 {
                assert!(r.reason().contains("of its size"), "{}", r.reason());
            }
        }
        let unknown = at(ContactLoad {
            unknown_collider_speed: true,
            ..ContactLoad::default()
        });
        assert_eq!(unknown.integrator, Integrator::SemiImplicitEuler);
        assert!(
            unknown.reason().contains("did not give"),
            "{}",
            unknown.reason()
        );
        assert_eq!(at(ContactLoad::default()).rule, Rule::Cost);
    }

    #[test]
    fn the_fastest_surface_point_of_a_turning_body() {
        // 90° about z over frames 1–2 at 24 fps, linear: ω = (π/2)·24 rad/s; at 0.1 m from the
        // axis, 0.1 ω m/s, plus nothing for the still translation.
        let pose = |f: f32| {
            let a = (f - 1.0).clamp(0.0, 1.0) * std::f32::consts::FRAC_PI_2;
            nalgebra::Isometry3::rotation(nalgebra::Vector3::z() * a)
        };
        let v = fastest_surface_speed(pose, 0.1, 1, 3, 24.0);
        let expected = 0.1 * std::f64::consts::FRAC_PI_2 * 24.0;
        assert!(
            (v - expected).abs() < 1e-4 * expected,
            "{v} against {expected}"
        );
    }

    #[test]
    fn a_fixed_count_below_the_stability_bound_takes_bdf2() {
        let step = 1.0 / 24.0;
        let b = bound(step / 100.0 / hair_core::integrate::stability::AUTO_SAFETY);
        let below = IntegratorChoice::Auto.resolve(
            StrandModel::MassSpring,
            &settings(Substeps::Fixed(20)),
            &b,
            0.0,
            &ContactLoad::default(),
        );
        assert_eq!(below.integrator, Integrator::Bdf2);
        let within = IntegratorChoice::Auto.resolve(
            StrandModel::MassSpring,
            &settings(Substeps::Fixed(200)),
            &b,
            0.0,
            &ContactLoad::default(),
        );
        assert_eq!(within.integrator, Integrator::SemiImplicitEuler);
        assert_eq!(
            (within.explicit_substeps, within.implicit_substeps),
            (200, 200)
        );
    }

    #[test]
    fn named_integrators_and_other_models_are_kept() {
        let s = settings(Substeps::Auto);
        let b = bound(1e-6);
        let named = IntegratorChoice::Named(Integrator::Xpbd);
        assert_eq!(
            named
                .resolve(
                    StrandModel::MassSpring,
                    &s,
                    &b,
                    3.0,
                    &ContactLoad::default()
                )
                .integrator,
            Integrator::Xpbd
        );
        assert!(
            !named
                .resolve(
                    StrandModel::MassSpring,
                    &s,
                    &b,
                    0.0,
                    &ContactLoad::default()
                )
                .auto
        );
        assert_eq!(
            IntegratorChoice::Auto
                .resolve(StrandModel::Rod, &s, &b, 0.0, &ContactLoad::default())
                .integrator,
            Integrator::SemiImplicitEuler
        );
    }

    #[test]
    fn spellings_round_trip_and_unknown_ones_name_the_choices() {
        #[derive(Deserialize, Serialize)]
        struct S {
            integrator: IntegratorChoice,
        }
        for word in [
            "auto",
            "semi-implicit-euler",
            "implicit-euler",
            "xpbd",
            "explicit-euler",
        ] {
            let s: S = toml::from_str(&format!("integrator = {word:?}")).unwrap();
            assert_eq!(s.integrator.to_string(), word);
            assert_eq!(
                toml::to_string(&s).unwrap().trim(),
                format!("integrator = {word:?}")
            );
        }
        let e = toml::from_str::<S>("integrator = \"rk4\"")
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("\"rk4\"") && e.contains("\"auto\""), "{e}");
    }
}
