//! Hair–object collision (seed 001, "Hair-Object collision"): hair points are spheres of their
//! radius, pairs are found once per collision step through rapier's query pipeline and reused in
//! the force substeps, and the response follows Choe et al. 2005 ("A Mass-Spring Model for Hair
//! Simulation", SIGGRAPH 2005): penetrating normal motion is stopped within one substep, and a
//! contacting point gets no outward velocity beyond what reaches the surface (no bouncing), with
//! Coulomb-like friction against the collider's surface velocity.
//!
//! # Pieces
//! - [`collider`]: what a collider is ([`Collider`]: sphere, capsule, triangle mesh; thickness,
//!   friction) and how meshes become solids or two-sided shells ([`MeshKind`]).
//! - [`collider_set`]: the set ([`Colliders`]: a rapier `ColliderSet` and `BroadPhaseBvh`), each
//!   collider's rigid pose at the start and end of the frame, and fast-motion stepping.
//! - [`deforming`]: mesh colliders whose vertices move per frame ([`Colliders::set_vertices`]) and
//!   the scalp collider following a deformed scalp: the model, what is exact, the cost.
//! - [`settings`]: [`ContactSettings`] (fast-motion tolerance, push-out speed).
//! - `detect`: detection once per step (query radius from relative motion, clearance skip, rapier
//!   broad phase, parry narrow phase, the contact's surface model).
//! - `coupling`: contacts solved together with the length constraints after the position update.
//! - `escapes`: the frame-end check that puts back points which outran detection's margin or
//!   ended deeper than the contact model's error.
//! - `fast_projection`: an exact shortcut for the narrow phase near a convex part of a mesh.
//! - `penalty`: the response in the substeps, in SIMD lanes (lanes = strands).
//! - `math`: the one place where nalgebra and rapier/parry's glam types meet.
//!
//! # Use
//! ```
//! use hair_core::contacts::{Collider, Colliders};
//! use nalgebra::{Isometry3, Vector3};
//!
//! let mut colliders = Colliders::new();
//! let ball = colliders
//!     .insert(Collider::sphere(0.1).with_thickness(1e-3).with_friction(0.3), Isometry3::identity())
//!     .unwrap();
//! // Every frame: the pose at the frame's end, then MassSpringSolver::step_frame_with_colliders.
//! colliders.set_pose(ball, Isometry3::translation(0.0, 0.0, 0.05)).unwrap();
//!
//! // A deforming mesh: its body-space vertices at the frame's end, same count and order as the
//! // mesh it was inserted with.
//! let body = hair_core::TriMesh::uv_sphere(0.2, 16, 8).unwrap();
//! let chest = colliders.insert(Collider::mesh(body.clone()), Isometry3::identity()).unwrap();
//! let breathed: Vec<Vector3<f32>> = body.positions().iter().map(|p| p * 1.02).collect();
//! colliders.set_vertices(chest, &breathed).unwrap();
//! ```
//!
//! # What is implemented, and its limits
//! - **Response** (`penalty`): after the velocity update and the damping sub-loop, a point whose
//!   normal velocity would take it into the surface within the substep gets the normal velocity
//!   that lands it exactly on the surface; a point already inside is moved out within the substep
//!   as a position correction that keeps no outward velocity (the depth it had at detection at
//!   most at [`ContactSettings::max_push_speed`], anything the step added at once); the kept
//!   normal velocity never exceeds what reaches the surface nor the surface's own normal speed
//!   (no bounce); friction removes at most μ × the normal velocity
//!   change from the tangential velocity relative to the surface. It is the limit of Choe et al.'s
//!   penalty spring stiff enough to stop penetration in one substep, applied as the impulse it
//!   would deliver; it adds no stiffness, so it does not change the stability bound.
//! - **One contact per point and step**, with the collider whose surface is nearest (smallest
//!   signed distance). A point squeezed between two colliders respects only the nearer one in a
//!   step, and hair pinched between two colliders that overlap (a ball passing through the head)
//!   is pulled through one of them and stretched.
//! - **Local surface model.** Within a step the surface near a contact is the contact's tangent
//!   plane or the sphere of its smallest curvature, moving with the collider. It is exact for
//!   translating spheres and planes at any speed, and conservative on other convex or saddle
//!   surfaces: hair sliding a distance `s` over them within a step is held off by up to
//!   `(κ_max − κ_min) s²/2`, not let in. Rotation is followed linearly; frames of fast-turning
//!   colliders are split into more steps until that error is below
//!   [`ContactSettings::tolerance`] ([`collider_set`]). On meshes the curvature comes from smooth
//!   vertex normals, so on a sharp-edged mesh the sphere can dip below a flat face next to an
//!   edge by about `κ s²/2`. The sphere's normal is the smooth normal interpolated from the
//!   vertex normals at the projection, not the facet's: a facet is tilted against the surface it
//!   approximates, and a sphere tangent to it let hair sliding `s` within a step in by that tilt
//!   × `s` (2.8 mm on the parity scene's head at one step per frame); the smooth sphere lies
//!   below the facets by at most their sagitta, which the hair radius covers.
//! - **Detection margin.** A point is only tested against a collider within its query radius
//!   `radius + thickness + 2|v_rel|Δt + |g|Δt² + 1 mm` (`v_rel` relative to the collider's
//!   material point where the hair point is). A point that accelerates beyond that within a step
//!   (a whipping strand) gets no contact in it. Without a strain limit (soft stretch springs,
//!   `max_strain` absent) points next to the root of a strand snapping taut were measured to go
//!   from rest to 4–5 m/s within one step, past the margin, and end the frame up to 2.2 cm inside
//!   the parity scene's head. The frame-end check (`escapes`) catches them: after a frame's last
//!   step every free point without a contact is checked against every collider (nearly free: it
//!   reads detection's distance bounds) and one closer than its radius plus the thickness is put
//!   back on the surface, its velocity into the surface removed; `FrameReport::escaped_points`
//!   counts them (34 point-frames in that scene; none with its strain limit). Within a frame of
//!   several collision steps the next step's detection pushes such a point out instead.
//! - **Frame-end depth.** The same check measures points in contact against the exact surface:
//!   one that the step's local model left deeper than 25 µm inside (beyond what remains of the
//!   depth found at detection) is moved back to that depth, and
//!   `FrameReport::deep_contact_points` counts them. Strands with a length limit (the strain
//!   limit, the inextensibility projection) are then brought back within it, the moved points
//!   held and their neighbours following, so a cached frame has no point deeper than 25 µm
//!   inside a collider except hair being eased out of a start inside it, and a point next to a
//!   root, which the limit keeps where the segment allows.
//! - **Resuming.** The scalp collider is built from the rest mesh (then put at the frame's deformed
//!   scalp by [`Colliders::place_scalp`], a deforming mesh at its vertices by
//!   [`Colliders::place_vertices`]: everything the shape holds is recomputed from the vertices and
//!   parry's refitted tree keeps the structure built from the rest mesh, so the shape is the same
//!   bits as the uninterrupted run's), a contact is computed from
//!   the feature (face, edge, vertex) found, not from the path that found it, and where parry's
//!   tree search answers (no warm start, or the shortcut could not certify) the shortcut is run
//!   again from the triangle it found. Detection's memory (distance bounds, warm-start
//!   triangles) then only saves work, and a run resumed from a cache, which starts without it,
//!   continues bit-identically (`collision_resume`: the turning built-in head, and the parity
//!   head cut to 6,000 strands). Before that last step, parry's search and the walk named
//!   different features for near-ties — the two halves of a flat quad, whose distances tie up to
//!   rounding, or a face against its edge within the fold tolerance (`FOLD`) — for 116 of
//!   200,000 random points near the parity head, and the parity scene resumed at frame 15 ended
//!   1,155 of its 1.02 M coordinates up to 3.7 µm off. Where neither path can certify (inside a
//!   solid, near a concave part) both answers come from parry's search, with the hint only
//!   bounding it; a near-tie there could still differ.
//! - **Order in the substep.** Contacts act after the damping sub-loop and before the position
//!   update; with a strain limit or the inextensibility projection on, the contacts are then
//!   solved together with it after the position update (`coupling`: a few Gauss–Seidel rounds,
//!   the push-out of a point found inside applied as a position correction its neighbours
//!   follow without gaining velocity), so the length constraint neither pulls contacts back
//!   into the collider nor hands the push-out on as motion.
//! - **Kinematic points** (roots, pinned points) are never pushed.
//! - **Deforming meshes** ([`deforming`]): the shape stands exactly at the linearly interpolated
//!   vertices at every step's start; within a step each contact's plane or sphere moves with its
//!   material point and turns with its triangle (exact where the neighbourhood moves rigidly);
//!   friction acts against the deformation's surface velocity. What changes of bending within a
//!   step do to the model (`Δκ δ²/2`) splits frames into more steps like rotation does. Each step
//!   whose shape moved pays a refit of the mesh (linear in its size; 50k vertices measured in
//!   `benches/deforming.rs`).
//! - **Scalp as collider** follows the scalp: its body transform as the pose and, when the scalp
//!   mesh handed to the solver is deformed beyond the body transform (by more than f32 rounding:
//!   5 µm near the origin, relative 5e-6 of the distance from it), its vertices. A rigid scalp
//!   never touches the shape (bit for bit a scalp collider that does not follow deformation).
//!   Hair whose rest shape lies closer to the scalp than its radius plus the thickness is pushed
//!   off.
//! - **Shells** (open or non-manifold meshes) have no inside: a point is kept on the side it is on
//!   at each step's start. A point that crossed a shell before detection saw it stays across.
//! - **Explicit Euler** moves points with the old velocity; the response is applied to that
//!   velocity too, so positions land on the surface as with semi-implicit Euler.
//! - **Cost when off**: with no collider (or none near any hair) nothing of this runs and the
//!   strands are bit-identical to a run without colliders.

pub mod collider;
pub mod collider_set;
pub(crate) mod coupling;
pub mod deforming;
pub(crate) mod detect;
pub(crate) mod escapes;
pub(crate) mod fast_projection;
pub(crate) mod math;
pub(crate) mod penalty;
pub mod settings;

pub use collider::{Collider, ColliderShape, MeshKind};
pub use collider_set::{ColliderId, Colliders};
pub use settings::ContactSettings;
