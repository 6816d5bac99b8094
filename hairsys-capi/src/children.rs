//! `HairsysChildren`: render children of a session's current frame, in buffers the library
//! owns and the host reads through [`HairsysChildrenView`].

use hair_core::StrandSet;
use hair_render::{ChildBuffers, ChildCount, ChildMode, ChildSettings, DisplayLod, Lod};
use hairsys::budget::{Budget, BYTES_PER_CHILD_POINT};

use crate::check;
use crate::error::{guard, Failure, HairsysStatus};
use crate::session::{with_session, HairsysSession};
use crate::types::{HairsysChildSettings, HairsysChildrenView};

/// Render children (opaque): flat buffers made by `hairsys_session_children`, owned by the
/// host, released with `hairsys_children_destroy`; independent of the session's lifetime.
pub struct HairsysChildren {
    buffers: ChildBuffers,
}

/// Fills `*out` with the library's default child settings (10 simple children per strand).
///
/// # Safety
/// `out` points to writable memory for the struct.
#[no_mangle]
pub unsafe extern "C" fn hairsys_child_settings_default(
    out: *mut HairsysChildSettings,
) -> HairsysStatus {
    guard(|| {
        let d = ChildSettings::default();
        let (interpolated, neighbours) = match d.mode {
            ChildMode::Simple => (0, 4),
            ChildMode::Interpolated { neighbours } => (1, neighbours),
        };
        let (per_parent, total) = match d.count {
            ChildCount::PerParent(n) => (n, 0),
            ChildCount::Total(t) => (0, t),
        };
        // SAFETY: the caller's promise.
        unsafe { check::out(out, "out")? }.write(HairsysChildSettings {
            per_parent,
            total,
            interpolated,
            neighbours,
            spread: d.spread,
            clump: d.shape.clump.factor,
            curl_radius: d.shape.curl.radius,
            curl_frequency: d.shape.curl.frequency,
            seed: d.seed,
            display: 0,
        });
        Ok(())
    })
}

/// The library's settings of `c`, and its level of detail.
fn settings(c: &HairsysChildSettings) -> Result<(ChildSettings, Lod), Failure> {
    check::finite(
        &[[c.spread, c.clump, c.curl_radius, c.curl_frequency]],
        "settings",
    )?;
    let mut s = ChildSettings {
        count: match c.total {
            0 => ChildCount::PerParent(c.per_parent),
            t => ChildCount::Total(t),
        },
        spread: c.spread,
        seed: c.seed,
        mode: if check::flag(c.interpolated, "interpolated")? {
            ChildMode::Interpolated {
                neighbours: c.neighbours,
            }
        } else {
            ChildMode::Simple
        },
        ..ChildSettings::default()
    };
    s.shape.clump.factor = c.clump;
    s.shape.curl.radius = c.curl_radius;
    s.shape.curl.frequency = c.curl_frequency;
    let lod = if check::flag(c.display, "display")? {
        Lod::Display(DisplayLod::default())
    } else {
        Lod::Render
    };
    Ok((s, lod))
}

/// Refuses children whose points would need more memory than the library's default budget
/// (8 GiB, `hairsys::budget`), before any is generated: counts come from the host unchecked.
fn check_budget(strands: &StrandSet, settings: &ChildSettings) -> Result<(), Failure> {
    let parents = strands.len();
    let children = match settings.count {
        ChildCount::PerParent(n) => f64::from(n) * parents as f64,
        ChildCount::Total(n) => n as f64,
    };
    let points_per_child = strands.point_count() as f64 / parents.max(1) as f64;
    Budget::default()
        .check_bytes(
            "children",
            children * points_per_child * BYTES_PER_CHILD_POINT as f64,
        )
        .map_err(|over| {
            Failure::argument(
                "settings",
                format!(
                    "{children} children of about {points_per_child:.0} points need about \
                     {:.1} GiB (limit {:.1} GiB): lower per_parent or total",
                    over.estimate / f64::from(1u32 << 30),
                    over.limit / f64::from(1u32 << 30)
                ),
            )
        })
}

/// Generates render children of the session's current frame with `settings` (rooted on the
/// current scalp) and writes their handle to `*out`.
///
/// # Safety
/// `session` is a live handle; `settings` points to a valid struct; `out` points to writable
/// memory for a pointer.
#[no_mangle]
pub unsafe extern "C" fn hairsys_session_children(
    session: *const HairsysSession,
    settings: *const HairsysChildSettings,
    out: *mut *mut HairsysChildren,
) -> HairsysStatus {
    // SAFETY: the caller's promise.
    unsafe {
        with_session(session, |s| {
            let out = check::out(out, "out")?;
            let (settings, lod) = self::settings(check::reference(settings, "settings")?)?;
            check_budget(s.strands(), &settings)?;
            let buffers = s.children(&settings, lod, None)?;
            out.write(Box::into_raw(Box::new(HairsysChildren { buffers })));
            Ok(())
        })
    }
}

/// Writes views of the children's arrays to `*out` (valid until the children are destroyed).
///
/// # Safety
/// `children` is a live handle; `out` points to writable memory for the struct.
#[no_mangle]
pub unsafe extern "C" fn hairsys_children_view(
    children: *const HairsysChildren,
    out: *mut HairsysChildrenView,
) -> HairsysStatus {
    guard(|| {
        // SAFETY: the caller's promise.
        let b = &unsafe { check::reference(children, "children")? }.buffers;
        // SAFETY: the caller's promise.
        unsafe { check::out(out, "out")? }.write(HairsysChildrenView {
            vertex_counts: b.vertex_counts.as_ptr(),
            curve_count: b.vertex_counts.len(),
            points: b.points.as_ptr(),
            point_count: b.points.len() / 3,
            widths: b.widths.as_ptr(),
            parent: b.parent.as_ptr(),
            root_uv: b
                .root_uv
                .as_ref()
                .map_or(std::ptr::null(), |uv| uv.as_ptr()),
        });
        Ok(())
    })
}

/// Destroys children. NULL is ignored.
///
/// # Safety
/// `children` is NULL or a live handle, not used again.
#[no_mangle]
pub unsafe extern "C" fn hairsys_children_destroy(children: *mut HairsysChildren) {
    // SAFETY: the caller's promise.
    unsafe { crate::check::destroy(children) }
}
