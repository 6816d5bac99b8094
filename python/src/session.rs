//! `hairsys.Session`: [`hairsys::Session`] for Python.
//!
//! # Positions without copies, and their lifetime
//! `Session.positions` and `Session.velocities` are read-only numpy arrays that view the
//! session's own buffers (the strands' `Vec<Vector3<f32>>`): no copy on read. The array's `base`
//! is the `Session` object, so the memory lives as long as any array viewing it. The buffers are
//! allocated once, when the session is built, and never reallocated: no method changes the
//! point count, and `restore` copies a snapshot into them in place. So an array taken once stays
//! valid and shows the current frame after every `step` and `restore` (copy it, e.g.
//! `np.array(s.positions)`, to keep a frame).
//!
//! `step` releases the GIL while it computes and holds the session mutably borrowed meanwhile:
//! any other call on the same session from another thread (reading `positions` included) raises
//! `RuntimeError` ("already borrowed") instead of waiting or reading a frame in the middle of
//! its update. An array taken *before* the step still views the buffers: do not read it from
//! another thread while the same session steps (the values are being overwritten); reading
//! other sessions, or other Python work, runs in parallel freely.
//!
//! # Failures
//! Errors are typed exceptions (see [`crate::errors`]). A step that fails leaves the session
//! failed: the next `step` raises `SessionFailedError` until `restore` puts a snapshot back. A
//! caught Rust panic marks the session broken for good.

use std::path::PathBuf;
use std::sync::{Arc, Mutex, MutexGuard};

use hair_cache::{Compression, Precision, WriterOptions};
use hair_core::{ColliderId, FrameReport};
use hair_render::{ChildCount, ChildMode, ChildSettings, DisplayLod, Lod};
use nalgebra::Isometry3;
use numpy::ndarray::ArrayView2;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{IntoPyDict, PyDict};

use crate::arrays::{float_rows, floats, isometry, rows_to_numpy, with_float_rows};
use crate::children::Children;
use crate::errors::{argument, guard, panic_message, to_py, InternalError};
use crate::groom::groom_options;

/// A hair simulation driven frame by frame.
///
/// Build one with `Session.from_scene(path)` or `Session.from_groom(...)`; each `step()`
/// advances one frame (1/fps s). Read `positions`/`velocities` (read-only float32 views of
/// shape (P, 3), m and m/s, no copy) with `strand_offsets` (strand s is points
/// `offsets[s]:offsets[s+1]`).
#[pyclass(name = "Session", module = "hairsys")]
pub struct PySession {
    /// The session. A `Mutex` only to make the class `Sync` (a cache writer's compressor is
    /// not): pyo3's borrow flag already keeps calls apart, so the lock is never contended, and
    /// `&mut self` methods reach the session without locking (`Mutex::get_mut`).
    inner: Mutex<hairsys::Session>,
    /// Set when a panic was caught in a call: the state may be half-updated.
    broken: Option<String>,
}

/// A copy of a session's state at one frame (`Session.snapshot()`), for `Session.restore`.
#[pyclass(name = "Snapshot", module = "hairsys", frozen)]
pub struct PySnapshot {
    inner: hairsys::Snapshot,
}

#[pymethods]
impl PySnapshot {
    /// The frame the snapshot holds.
    #[getter]
    fn frame(&self) -> u32 {
        self.inner.frame()
    }

    fn __repr__(&self) -> String {
        format!("<hairsys.Snapshot of frame {}>", self.inner.frame())
    }
}

impl PySession {
    fn wrap(inner: hairsys::Session, threads: Option<usize>) -> PyResult<Self> {
        let mut inner = inner;
        if let Some(n) = threads {
            if n == 0 {
                return Err(argument("threads", "is 0: give at least 1 thread, or None"));
            }
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| InternalError::new_err(format!("cannot start {n} threads: {e}")))?;
            inner.set_thread_pool(Arc::new(pool));
        }
        Ok(Self {
            inner: Mutex::new(inner),
            broken: None,
        })
    }

    /// The session, shared (a panic inside is caught and marks the session broken, so a
    /// poisoned lock holds nothing more than `broken` says).
    fn session(&self) -> MutexGuard<'_, hairsys::Session> {
        self.inner.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// The session, exclusively, without locking.
    fn session_mut(&mut self) -> &mut hairsys::Session {
        self.inner.get_mut().unwrap_or_else(|p| p.into_inner())
    }

    /// A collider id from Python; a negative or too large one is an ArgumentError (the session
    /// refuses ids it does not have by name).
    fn collider_id(&self, id: i64) -> PyResult<ColliderId> {
        u32::try_from(id).map(ColliderId).map_err(|_| {
            argument(
                &format!("collider {id}"),
                format!(
                    "does not exist: this session has {} collider(s)",
                    self.session().colliders().len()
                ),
            )
        })
    }

    fn check(&self) -> PyResult<()> {
        match &self.broken {
            Some(why) => Err(InternalError::new_err(format!(
                "this session is broken by an earlier internal error ({why}); build a new one"
            ))),
            None => Ok(()),
        }
    }

    /// A read-only `(P, 3)` view of `rows` whose base is `owner`.
    fn view<'py>(
        owner: &Bound<'py, PySession>,
        rows: impl Fn(&hairsys::Session) -> &[[f32; 3]],
    ) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let this = owner.try_borrow()?;
        this.check()?;
        let session = this.session();
        let rows = rows(&session);
        let view = ArrayView2::from_shape((rows.len(), 3), rows.as_flattened())
            .map_err(|e| InternalError::new_err(e.to_string()))?;
        // SAFETY: the array borrows memory owned by the session and keeps the `Session` object
        // alive through its base; the buffer is never reallocated (see the module docs).
        let array = unsafe { PyArray2::borrow_from_array(&view, owner.clone().into_any()) };
        array.call_method(
            "setflags",
            (),
            Some(&[("write", false)].into_py_dict(owner.py())?),
        )?;
        Ok(array)
    }

    /// Force field `index`, or an ArgumentError naming the index and the count.
    fn field_mut(&mut self, index: usize) -> PyResult<&mut hair_core::ForceField> {
        self.check()?;
        let fields = self.session_mut().fields_mut();
        let n = fields.len();
        fields.get_mut(index).ok_or_else(|| {
            argument(
                "index",
                format!("field {index} does not exist ({n} fields)"),
            )
        })
    }

    fn params(&mut self) -> PyResult<&mut hair_core::HairParams> {
        self.check()?;
        self.session_mut().params_mut().ok_or_else(|| {
            argument(
                "parameters",
                "this session's model (rod) fixes its parameters at creation",
            )
        })
    }
}

#[pymethods]
impl PySession {
    /// A session of the scene file at `path` (TOML, see `hairsys scene init`); the built-in
    /// default scene when `path` is None. `threads`: size of the session's own thread pool
    /// (None: rayon's global pool). The scene's keyframes move the scalp and colliders for every
    /// frame the host does not set them. Raises SceneError.
    #[staticmethod]
    #[pyo3(signature = (path=None, *, threads=None))]
    fn from_scene(py: Python<'_>, path: Option<PathBuf>, threads: Option<usize>) -> PyResult<Self> {
        guard(|| {
            let session = py.detach(|| {
                let scene = match &path {
                    Some(p) => hairsys::scene::SceneFile::load(p)?,
                    None => hairsys::scene::SceneFile::builtin_default(),
                };
                hairsys::Session::from_scene(&scene)
            });
            Self::wrap(session.map_err(to_py)?, threads)
        })
    }

    /// A session of a groom on a scalp given as arrays (m, Z up, world space at the first
    /// frame): `scalp_vertices` (V, 3) float, `scalp_triangles` (T, 3) int, `curve_points`
    /// (P, 3) float (every curve root first, curve after curve), `curve_counts` (C,) int
    /// (points per curve, ≥ 2, adding up to P). Keyword options (units in the stub
    /// `hairsys.pyi`): scalp_uvs, goal_weights (P,), pinned (P,) bool, strand_scales (dict
    /// of (C,) factors: stretch, bend, goal, damping, drag), sim_hairs (None: simulate the curves
    /// themselves, in order; an int: interpolate that many hairs from the curves as guides),
    /// k, points, seed, fps, first_frame, steps, substeps, integrator, damping_iterations, gravity,
    /// stretch_stiffness, bend_stiffness, goal_stiffness, stretch_damping, air_drag,
    /// mass_per_length, radius, goal_root, goal_tip, max_snap_distance, scalp_collider,
    /// scalp_thickness, scalp_friction, colliders (list of dicts), hair_hair_friction,
    /// hair_hair_cell_size, threads. Raises ArgumentError.
    #[staticmethod]
    #[pyo3(signature = (scalp_vertices, scalp_triangles, curve_points, curve_counts, **options))]
    fn from_groom(
        py: Python<'_>,
        scalp_vertices: &Bound<'_, PyAny>,
        scalp_triangles: &Bound<'_, PyAny>,
        curve_points: &Bound<'_, PyAny>,
        curve_counts: &Bound<'_, PyAny>,
        options: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        guard(|| {
            let input = crate::groom::GroomInput::read(
                scalp_vertices,
                scalp_triangles,
                curve_points,
                curve_counts,
                options,
            )?;
            let (opts, threads) = groom_options(options)?;
            let session = py.detach(|| hairsys::Session::from_groom(&input.arrays(), &opts));
            Self::wrap(session.map_err(to_py)?, threads)
        })
    }

    /// Advances one frame. `scalp_matrix`: the scalp's rigid transform (4, 4) for the new
    /// frame (a scaled or sheared matrix is refused); `scalp_vertices`: the deformed scalp
    /// (V, 3) float32/float64, m, in the scalp's body space placed by `scalp_matrix` (world
    /// space with no matrix). Neither: the scene's keyframes (or the scalp stays). Releases the
    /// GIL while it computes. Returns a dict of the frame's figures (frame, substeps, steps,
    /// point_substeps, contact_points, max_stretch, phase_ms: the library's wall time by phase in
    /// ms, a dict with roots, strands, contacts, volume and fields, and step_ms: the library
    /// step's wall time). Raises ArgumentError, SolverError,
    /// SessionFailedError, CacheError.
    #[pyo3(signature = (scalp_matrix=None, scalp_vertices=None))]
    fn step<'py>(
        slf: &Bound<'py, Self>,
        scalp_matrix: Option<&Bound<'py, PyAny>>,
        scalp_vertices: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let py = slf.py();
        let mut this = slf.try_borrow_mut()?;
        this.check()?;
        let body = scalp_matrix
            .map(|m| isometry(m, "scalp_matrix"))
            .transpose()?;
        let set = guard(|| {
            match (scalp_vertices, body) {
                (Some(v), body) => {
                    let expected = this
                        .session_mut()
                        .scalp()
                        .mesh
                        .as_ref()
                        .map_or("(V, 3)".to_string(), |m| {
                            format!("({}, 3)", m.positions().len())
                        });
                    with_float_rows::<3, _>(v, "scalp_vertices", &expected, |rows| {
                        this.session_mut()
                            .set_scalp_vertices(rows, body.unwrap_or_else(Isometry3::identity))
                            .map_err(to_py)
                    })?
                }
                (None, Some(body)) => this
                    .session_mut()
                    .set_scalp_transform(body)
                    .map_err(to_py)?,
                (None, None) => {}
            }
            Ok(())
        });
        set?;
        let inner = this.session_mut();
        let started = std::time::Instant::now();
        let result =
            py.detach(|| std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| inner.step())));
        let step_ms = started.elapsed().as_secs_f64() * 1e3;
        let report = match result {
            Ok(r) => r.map_err(to_py)?,
            Err(payload) => {
                let message = panic_message(&*payload);
                this.broken = Some(message.clone());
                return Err(InternalError::new_err(message));
            }
        };
        let d = report_dict(py, &report)?;
        d.set_item("step_ms", step_ms)?;
        Ok(d)
    }

    /// Positions of every point, m, shape (P, 3) float32, read-only, **no copy**: a view of the
    /// session's buffer whose base is this session (it shows the current frame after every
    /// step; copy it to keep a frame).
    #[getter]
    fn positions<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        guard(|| Self::view(slf, |s| s.positions()))
    }

    /// Velocities of every point, m/s, shape (P, 3) float32, read-only, no copy (like
    /// `positions`).
    #[getter]
    fn velocities<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        guard(|| Self::view(slf, |s| s.velocities()))
    }

    /// Strand s is points `strand_offsets[s]:strand_offsets[s+1]`; shape (strands + 1,) uint32.
    #[getter]
    fn strand_offsets<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<u32>>> {
        self.check()?;
        Ok(PyArray1::from_slice(py, self.session().strand_offsets()))
    }

    /// Number of strands.
    #[getter]
    fn strand_count(&self) -> usize {
        self.session().strands().len()
    }

    /// Number of points (rows of `positions`).
    #[getter]
    fn point_count(&self) -> usize {
        self.session().strands().point_count()
    }

    /// Frame number of the current state.
    #[getter]
    fn frame(&self) -> u32 {
        self.session().frame()
    }

    /// Frames per second (a step advances 1/fps s).
    #[getter]
    fn fps(&self) -> f32 {
        self.session().fps()
    }

    /// The time integrator the session runs (`"auto"` resolved when it was made): one of
    /// `"semi-implicit-euler"`, `"bdf2"`, `"implicit-euler"`, `"xpbd"`, `"explicit-euler"`; the
    /// rod and strip models, which keep their own schemes, give `"rod"` and `"strips"`.
    #[getter]
    fn integrator(&self) -> &'static str {
        match self.session().solver() {
            hair_core::StrandSolver::MassSpring(s) => {
                hairsys::scene::integrator::integrator_name(s.settings().integrator)
            }
            hair_core::StrandSolver::Rod(_) => "rod",
            hair_core::StrandSolver::Strips(_) => "strips",
        }
    }

    /// Number of colliders (ids 0 … n−1; the scalp collider, if any, is one of them).
    #[getter]
    fn collider_count(&self) -> usize {
        self.session().colliders().len()
    }

    /// Poses collider `id` (rigid 4×4 matrix, body to world, m) at the end of the next frame.
    /// Raises ArgumentError for an id that does not exist, the scalp collider, or a matrix
    /// that is not rigid.
    fn set_collider_pose(&mut self, id: i64, matrix: &Bound<'_, PyAny>) -> PyResult<()> {
        self.check()?;
        let id = self.collider_id(id)?;
        let pose = isometry(matrix, "matrix")?;
        guard(|| {
            self.session_mut()
                .set_collider_pose(id, pose)
                .map_err(to_py)
        })
    }

    /// Deforms mesh collider `id`: `vertices` (V, 3) float, its shape at the end of the next
    /// frame in its body space (same count and order as the mesh it was made with); within the
    /// frame each vertex moves in a straight line and friction acts against that motion. Raises
    /// ArgumentError for an id that does not exist, a sphere or capsule, a wrong count or a
    /// non-finite vertex.
    fn set_collider_vertices(&mut self, id: i64, vertices: &Bound<'_, PyAny>) -> PyResult<()> {
        self.check()?;
        let id = self.collider_id(id)?;
        with_float_rows::<3, _>(vertices, "vertices", "(V, 3)", |rows| {
            guard(|| {
                self.session_mut()
                    .set_collider_vertices(id, rows)
                    .map_err(to_py)
            })
        })
    }

    /// Sets the guides' pose for the next frame (animated guides): `points` (P, 3) float, m,
    /// every guide's points in the groom's order and point counts (`guide_point_counts`), in
    /// the scalp's body space at rest. The sim hairs' rest shapes are re-interpolated from it.
    /// Raises ArgumentError for a session without guides, a wrong point count or a non-finite
    /// point.
    fn set_guide_pose(&mut self, points: &Bound<'_, PyAny>) -> PyResult<()> {
        self.check()?;
        with_float_rows::<3, _>(points, "points", "(P, 3)", |rows| {
            guard(|| self.session_mut().set_guide_pose(rows).map_err(to_py))
        })
    }

    /// Sets the sim weight for the next frame instead of the scene's curve: 0 = simulation,
    /// 1 = exactly the animated guides, between a blend (times each hair's factor). Raises
    /// ArgumentError outside [0, 1] or for a session without guides.
    fn set_sim_weight(&mut self, weight: f32) -> PyResult<()> {
        self.check()?;
        guard(|| self.session_mut().set_sim_weight(weight).map_err(to_py))
    }

    /// Sets each sim hair's factor of the sim weight, (H,) float in [0, 1], kept until set
    /// again. Raises ArgumentError for a wrong count, a value outside [0, 1] or a session
    /// without guides.
    fn set_strand_sim_weights(&mut self, weights: &Bound<'_, PyAny>) -> PyResult<()> {
        self.check()?;
        let w = floats(weights, "weights", "(H,)")?;
        guard(|| self.session_mut().set_strand_sim_weights(&w).map_err(to_py))
    }

    /// Names of the scene's `[[regions]]`, in file order (empty without regions).
    #[getter]
    fn region_names(&self) -> PyResult<Vec<String>> {
        self.check()?;
        Ok(self.session().region_names())
    }

    /// Strand indices of region `name`, increasing. Raises ArgumentError for an unknown name.
    fn region_strands(&self, name: &str) -> PyResult<Vec<usize>> {
        self.check()?;
        self.session().region_strands(name).map_err(to_py)
    }

    /// Region `name`'s parameters as a dict: `stretch_stiffness`, `bend_stiffness`,
    /// `goal_stiffness` (N/m), `stretch_damping`, `air_drag` (1/s), `mass_scale`,
    /// `radius_scale`; None = the scene's `[physics]` value (or factor 1).
    fn region_params<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyDict>> {
        self.check()?;
        let p = self.session().region_params(name).map_err(to_py)?;
        let d = PyDict::new(py);
        for (key, value) in region_entries(&p) {
            d.set_item(key, value)?;
        }
        Ok(d)
    }

    /// Changes region `name`'s springs, damping and drag from the next frame on: `params` maps
    /// any of `stretch_stiffness`, `bend_stiffness`, `goal_stiffness`, `stretch_damping`,
    /// `air_drag` to a value in `[physics]`'s units, or None for the scene's; keys left out keep
    /// their current value. The substep stays (a much stiffer region may make the next step
    /// unstable, which it reports). Raises ArgumentError for an unknown region or key, a bad
    /// value, or a mass or radius factor (fixed when the scene is built).
    fn set_region_params(&mut self, name: &str, params: &Bound<'_, PyDict>) -> PyResult<()> {
        self.check()?;
        let mut p = self.session().region_params(name).map_err(to_py)?;
        for (key, value) in params.iter() {
            let key: String = key.extract()?;
            let value: Option<f32> = value
                .extract()
                .map_err(|_| argument(&key, "give a number or None"))?;
            let slot = match key.as_str() {
                "stretch_stiffness" => &mut p.stretch_stiffness,
                "bend_stiffness" => &mut p.bend_stiffness,
                "goal_stiffness" => &mut p.goal_stiffness,
                "stretch_damping" => &mut p.stretch_damping,
                "air_drag" => &mut p.air_drag,
                "mass_scale" | "radius_scale" => {
                    return Err(argument(
                        &key,
                        "is fixed when the scene is built; set it in the scene's [[regions]]",
                    ))
                }
                _ => {
                    return Err(argument(
                        &key,
                        "is not a region parameter; use stretch_stiffness, bend_stiffness, \
                         goal_stiffness, stretch_damping or air_drag",
                    ))
                }
            };
            *slot = value;
        }
        guard(|| self.session_mut().set_region_params(name, p).map_err(to_py))
    }

    /// Point count of each guide, in the groom's order (empty without guides).
    #[getter]
    fn guide_point_counts(&self) -> PyResult<Vec<usize>> {
        self.check()?;
        Ok(self
            .session()
            .guide_animation()
            .map(|a| a.guide_points().to_vec())
            .unwrap_or_default())
    }

    /// (P, 3) float32: the guides' groom points, m, in the scalp's body space at rest, every
    /// guide in order (`guide_point_counts` each): edit and pass to `set_guide_pose`. Empty
    /// without guides.
    #[getter]
    fn guide_groom_points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        self.check()?;
        let points = self
            .session()
            .guide_animation()
            .map(|a| a.groom_points())
            .unwrap_or_default();
        Ok(rows_to_numpy(
            py,
            points.into_iter().map(nalgebra::Vector3::from).collect(),
        ))
    }

    /// Strand indices `(start, end)` of the sim hairs the guides drive (None without guides).
    #[getter]
    fn guided_strands(&self) -> PyResult<Option<(usize, usize)>> {
        self.check()?;
        Ok(self.session().guide_animation().map(|a| {
            let r = a.strands();
            (r.start, r.end)
        }))
    }

    /// Gravity, m/s², as (x, y, z).
    #[getter]
    fn get_gravity(&mut self) -> PyResult<[f32; 3]> {
        Ok(self.params()?.gravity)
    }

    #[setter]
    fn set_gravity(&mut self, value: [f32; 3]) -> PyResult<()> {
        if !value.iter().all(|c| c.is_finite()) {
            return Err(argument("gravity", "is not finite: give (x, y, z) in m/s²"));
        }
        self.params()?.gravity = value;
        Ok(())
    }

    /// Goal spring stiffness, N/m (times each point's goal weight); checked at the next step.
    #[getter]
    fn get_goal_stiffness(&mut self) -> PyResult<f32> {
        Ok(self.params()?.goal_stiffness)
    }

    #[setter]
    fn set_goal_stiffness(&mut self, value: f32) -> PyResult<()> {
        self.params()?.goal_stiffness = value;
        Ok(())
    }

    /// Air drag, 1/s (decay rate of velocity in still air); checked at the next step.
    #[getter]
    fn get_air_drag(&mut self) -> PyResult<f32> {
        Ok(self.params()?.air_drag)
    }

    #[setter]
    fn set_air_drag(&mut self, value: f32) -> PyResult<()> {
        self.params()?.air_drag = value;
        Ok(())
    }

    /// Bending stiffness, N/m; checked at the next step.
    #[getter]
    fn get_bend_stiffness(&mut self) -> PyResult<f32> {
        Ok(self.params()?.bend_stiffness)
    }

    #[setter]
    fn set_bend_stiffness(&mut self, value: f32) -> PyResult<()> {
        self.params()?.bend_stiffness = value;
        Ok(())
    }

    /// Number of force fields (wind, vortex, …).
    #[getter]
    fn field_count(&mut self) -> PyResult<usize> {
        self.check()?;
        Ok(self.session_mut().fields_mut().len())
    }

    /// Strength of force field `index` at the next frame.
    fn field_strength(&mut self, index: usize) -> PyResult<f32> {
        self.check()?;
        let frame = self.session_mut().frame() as f32 + 1.0;
        let fields = self.session_mut().fields_mut();
        let n = fields.len();
        let f = fields.get(index).ok_or_else(|| {
            argument(
                "index",
                format!("field {index} does not exist ({n} fields)"),
            )
        })?;
        Ok(f.strength.at(frame))
    }

    /// Sets force field `index`'s strength (constant from now on, replacing its keys).
    fn set_field_strength(&mut self, index: usize, value: f32) -> PyResult<()> {
        if !value.is_finite() {
            return Err(argument("value", "is not finite"));
        }
        self.field_mut(index)?.strength = hair_core::Strength::Constant(value);
        Ok(())
    }

    /// Sets force field `index`'s direction (x, y, z), any length but not zero: the wind's flow,
    /// the vortex's and a tube falloff's axis.
    fn set_field_direction(&mut self, index: usize, direction: [f32; 3]) -> PyResult<()> {
        let d = nalgebra::Vector3::from(direction);
        if !(d.iter().all(|c| c.is_finite()) && d.norm() > 0.0) {
            return Err(argument(
                "direction",
                format!("= {direction:?}: give a finite, non-zero (x, y, z)"),
            ));
        }
        self.field_mut(index)?.direction = d / d.norm();
        Ok(())
    }

    /// Sets force field `index`'s center (x, y, z), m: the vortex's axis point, a point force's
    /// source and the falloff's origin.
    fn set_field_center(&mut self, index: usize, center: [f32; 3]) -> PyResult<()> {
        if !center.iter().all(|c| c.is_finite()) {
            return Err(argument(
                "center",
                format!("= {center:?}: give a finite (x, y, z) in m"),
            ));
        }
        self.field_mut(index)?.center = nalgebra::Vector3::from(center);
        Ok(())
    }

    /// Hair–hair friction (0–1), or None when hair–hair is off.
    #[getter]
    fn get_hair_hair_friction(&mut self) -> PyResult<Option<f32>> {
        self.check()?;
        Ok(self.session_mut().hair_hair_mut().map(|h| h.friction))
    }

    #[setter]
    fn set_hair_hair_friction(&mut self, value: f32) -> PyResult<()> {
        self.check()?;
        if !(0.0..=1.0).contains(&value) {
            return Err(argument(
                "hair_hair_friction",
                format!("= {value}: give 0 to 1"),
            ));
        }
        match self.session_mut().hair_hair_mut() {
            Some(h) => {
                h.friction = value;
                Ok(())
            }
            None => Err(argument(
                "hair_hair_friction",
                "hair–hair is off in this session (give [hair_hair] in the scene, or \
                 hair_hair_friction to from_groom)",
            )),
        }
    }

    /// A copy of the state at the current frame, for `restore` (scrubbing).
    fn snapshot(&self) -> PyResult<PySnapshot> {
        self.check()?;
        guard(|| {
            Ok(PySnapshot {
                inner: self.session().snapshot(),
            })
        })
    }

    /// Puts the session back in the state of `snapshot` (of this session) and clears a failed
    /// step; stepping on gives the same bits as from where it was taken. Refused while a cache
    /// is being written.
    fn restore(&mut self, snapshot: &PySnapshot) -> PyResult<()> {
        self.check()?;
        guard(|| self.session_mut().restore(&snapshot.inner).map_err(to_py))
    }

    /// Starts writing an MCAP cache at `path` (as `path.partial` until `finish_cache`): the
    /// current frame now, then every step. `compression`: "none", "lz4" or "zstd";
    /// `quantize`: 16-bit positions and velocities.
    #[pyo3(signature = (path, *, compression="none", quantize=false))]
    fn write_cache(&mut self, path: PathBuf, compression: &str, quantize: bool) -> PyResult<()> {
        self.check()?;
        let compression = match compression {
            "none" => Compression::None,
            "lz4" => Compression::Lz4,
            "zstd" => Compression::Zstd,
            other => {
                return Err(argument(
                    "compression",
                    format!("= {other:?}: give \"none\", \"lz4\" or \"zstd\""),
                ))
            }
        };
        let options = WriterOptions {
            compression,
            precision: if quantize {
                Precision::Quantized16
            } else {
                Precision::F32
            },
            ..WriterOptions::default()
        };
        guard(|| self.session_mut().record(&path, options).map_err(to_py))
    }

    /// Finishes the cache being written (index, summary, renamed to its final name); returns
    /// a dict: path, frames, first_frame, last_frame, fps, strands, points, bytes.
    fn finish_cache<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.check()?;
        let s = guard(|| self.session_mut().finish_recording().map_err(to_py))?;
        let d = PyDict::new(py);
        d.set_item("path", s.path)?;
        d.set_item("frames", s.frames)?;
        d.set_item("first_frame", s.first_frame)?;
        d.set_item("last_frame", s.last_frame)?;
        d.set_item("fps", s.fps)?;
        d.set_item("strands", s.strands)?;
        d.set_item("points", s.points)?;
        d.set_item("bytes", s.bytes)?;
        Ok(d)
    }

    /// Render children (see `hairsys.Children`) of the current frame, or of `positions` (P, 3)
    /// (m, world space, the strands' points in order: a cached frame) on the scalp at
    /// `scalp_vertices` (V, 3) (m, world space; None: the current scalp), without stepping:
    /// `per_parent` children around every strand, or `total` in all; `interpolated` roots them
    /// between `neighbours` parents; `spread` (m) is the root disc of simple children;
    /// `clump` (−1–1), `curl_radius` (m), `curl_frequency` (turns/m), `roughness` (m, uniform
    /// noise), `roughness_endpoint` (m, at the tip), `length_variation` (0–0.99) shape them;
    /// `root_width` and `tip_width` (m, diameters) taper them; `subdivisions` (1–64) are the
    /// Catmull–Rom pieces per parent segment at render level; `display` uses the display level
    /// of detail (`display_fraction` of the children, the parents' own points).
    #[pyo3(signature = (*, per_parent=10, total=None, interpolated=false, neighbours=4,
        spread=0.005, clump=0.0, curl_radius=0.0, curl_frequency=0.0, roughness=0.0,
        roughness_endpoint=0.0, length_variation=0.0, root_width=80e-6, tip_width=20e-6,
        subdivisions=4, seed=0, display=false, display_fraction=0.1, positions=None,
        scalp_vertices=None))]
    #[allow(clippy::too_many_arguments)]
    fn children(
        &self,
        py: Python<'_>,
        per_parent: u32,
        total: Option<u64>,
        interpolated: bool,
        neighbours: u32,
        spread: f32,
        clump: f32,
        curl_radius: f32,
        curl_frequency: f32,
        roughness: f32,
        roughness_endpoint: f32,
        length_variation: f32,
        root_width: f32,
        tip_width: f32,
        subdivisions: u32,
        seed: u64,
        display: bool,
        display_fraction: f32,
        positions: Option<&Bound<'_, PyAny>>,
        scalp_vertices: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Children> {
        self.check()?;
        let mut settings = ChildSettings {
            count: match total {
                Some(t) => ChildCount::Total(t),
                None => ChildCount::PerParent(per_parent),
            },
            spread,
            seed,
            subdivisions,
            mode: if interpolated {
                ChildMode::Interpolated { neighbours }
            } else {
                ChildMode::Simple
            },
            ..ChildSettings::default()
        };
        settings.shape.clump.factor = clump;
        settings.shape.curl.radius = curl_radius;
        settings.shape.curl.frequency = curl_frequency;
        settings.shape.roughness.uniform = roughness;
        settings.shape.roughness.endpoint = roughness_endpoint;
        settings.shape.length_variation = length_variation;
        settings.shape.taper.root = root_width;
        settings.shape.taper.tip = tip_width;
        let lod = if display {
            Lod::Display(DisplayLod {
                fraction: display_fraction,
                ..DisplayLod::default()
            })
        } else {
            Lod::Render
        };
        let (points, vertices) = {
            let session = self.session();
            let points = positions
                .map(|p| {
                    let n = session.strands().point_count();
                    float_rows::<3>(p, "positions", &format!("({n}, 3)"))
                })
                .transpose()?;
            let vertices = scalp_vertices
                .map(|v| {
                    let n = session.rest_scalp().map_or(0, |m| m.positions().len());
                    float_rows::<3>(v, "scalp_vertices", &format!("({n}, 3)"))
                })
                .transpose()?;
            (points, vertices)
        };
        if vertices.is_some() && points.is_none() {
            return Err(argument(
                "scalp_vertices",
                "give positions with scalp_vertices (the current frame keeps its own scalp)",
            ));
        }
        let inner = &self.inner;
        let buffers = py
            .detach(|| {
                std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    let session = inner.lock().unwrap_or_else(|p| p.into_inner());
                    match &points {
                        Some(points) => {
                            session.children_at(points, vertices.as_deref(), &settings, lod)
                        }
                        None => session.children(&settings, lod, None),
                    }
                }))
            })
            .map_err(|p| InternalError::new_err(panic_message(&*p)))?
            .map_err(to_py)?;
        Children::new(buffers)(py)
    }

    fn __repr__(&self) -> String {
        let s = self.session();
        format!(
            "<hairsys.Session frame {} · {} strands · {} points · {} fps>",
            s.frame(),
            s.strands().len(),
            s.strands().point_count(),
            s.fps()
        )
    }
}

/// The figures of a frame as a dict.
fn report_dict<'py>(py: Python<'py>, r: &FrameReport) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("frame", r.frame)?;
    d.set_item("substeps", r.substeps)?;
    d.set_item("steps", r.steps)?;
    d.set_item("point_substeps", r.point_substeps)?;
    d.set_item("contact_points", r.contact_points)?;
    d.set_item("max_stretch", r.max_stretch)?;
    let t = &r.times;
    let phases = PyDict::new(py);
    for (name, time) in [
        ("roots", t.roots),
        ("strands", t.strands),
        ("contacts", t.contacts),
        ("volume", t.volume),
        ("fields", t.fields),
    ] {
        phases.set_item(name, time.as_secs_f64() * 1e3)?;
    }
    d.set_item("phase_ms", phases)?;
    Ok(d)
}

/// A region's parameters as (key, value) pairs for Python (None = the scene's).
fn region_entries(p: &hairsys::scene::regions::RegionParams) -> [(&'static str, Option<f32>); 7] {
    [
        ("stretch_stiffness", p.stretch_stiffness),
        ("bend_stiffness", p.bend_stiffness),
        ("goal_stiffness", p.goal_stiffness),
        ("stretch_damping", p.stretch_damping),
        ("air_drag", p.air_drag),
        ("mass_scale", p.mass_scale),
        ("radius_scale", p.radius_scale),
    ]
}
