//! Hair self-shadowing and hair shadows on the meshes, from one depth map seen from the key light.
//!
//! A hair volume lit from one side is bright at its surface and darker inside, and the scalp
//! under it is dark; without that a preview looks flat. Full deep shadow maps (Lokovic & Veach,
//! SIGGRAPH 2000) store the light's transmittance as a function of depth per texel; this keeps
//! only their first sample, the depth of the nearest hair or mesh to the light, and assumes hair
//! of uniform density behind it, as in the one-layer approximations of real-time hair
//! (cf. Yuksel & Keyser, "Deep Opacity Maps", Eurographics 2008, whose layers start at the same
//! nearest depth): a point `Δ` behind the first surface along the light receives
//! `exp(−Δ / shadow_depth)` of the key light. Meshes block light fully in the same way (a point
//! behind the head is `Δ ≥` a head's depth from it, so its key light is gone).
//!
//! The map is an orthographic view along the light over the scene's bounds, [`MAP_SIZE`]²
//! texels; hair is splatted along its segments, meshes are filled. Lookups average the
//! transmittance of the nearest 2 × 2 texels for hair and 4 × 4 for meshes (percentage-closer
//! filtering, Reeves et al. 1987), which softens texel edges and the shadow of a single strand.

use nalgebra::Vector3;

use super::scene::{Bounds, Mesh, Strands};

/// Texels along each side of the map.
const MAP_SIZE: usize = 512;

/// Depth map along the key light.
pub(crate) struct ShadowMap {
    /// Unit direction towards the light.
    to_light: Vector3<f32>,
    /// Unit axes of the map plane.
    axis_u: Vector3<f32>,
    axis_v: Vector3<f32>,
    /// Map coordinates of texel (0, 0)'s corner, meters along the axes.
    origin: [f32; 2],
    /// Texels per meter.
    scale: f32,
    /// Distance from the light plane of the nearest hair or mesh per texel, meters (∞: none).
    depth: Vec<f32>,
    /// 1 / shadow depth, 1/m.
    falloff: f32,
}

impl ShadowMap {
    /// A map of `strands` and `meshes` along `to_light` (unit), over `bounds`, for hair whose key
    /// light falls by e per `shadow_depth` meters (> 0).
    pub fn build(
        strands: Option<&Strands>,
        meshes: &[Mesh],
        bounds: &Bounds,
        to_light: Vector3<f32>,
        shadow_depth: f32,
    ) -> Self {
        let axis_u = to_light
            .cross(&Vector3::z())
            .try_normalize(1e-6)
            .unwrap_or_else(|| to_light.cross(&Vector3::x()).normalize());
        let axis_v = to_light.cross(&axis_u);
        let (mut lo, mut hi) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
        for c in bounds.corners() {
            let uv = [c.dot(&axis_u), c.dot(&axis_v)];
            for k in 0..2 {
                lo[k] = lo[k].min(uv[k]);
                hi[k] = hi[k].max(uv[k]);
            }
        }
        let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-6);
        // One texel of margin on each side so lookups never fall off the covered area.
        let scale = (MAP_SIZE - 2) as f32 / extent;
        let mut map = Self {
            to_light,
            axis_u,
            axis_v,
            origin: [lo[0] - 1.0 / scale, lo[1] - 1.0 / scale],
            scale,
            depth: vec![f32::INFINITY; MAP_SIZE * MAP_SIZE],
            falloff: 1.0 / shadow_depth,
        };
        for mesh in meshes {
            map.fill_mesh(mesh);
        }
        if let Some(s) = strands {
            map.splat_strands(s);
        }
        map
    }

    /// Texel coordinates (continuous) and depth of `p`.
    fn project(&self, p: &Vector3<f32>) -> [f32; 3] {
        [
            (p.dot(&self.axis_u) - self.origin[0]) * self.scale,
            (p.dot(&self.axis_v) - self.origin[1]) * self.scale,
            -p.dot(&self.to_light),
        ]
    }

    fn write(&mut self, x: i64, y: i64, d: f32) {
        if (0..MAP_SIZE as i64).contains(&x) && (0..MAP_SIZE as i64).contains(&y) {
            let t = &mut self.depth[y as usize * MAP_SIZE + x as usize];
            *t = t.min(d);
        }
    }

    fn fill_mesh(&mut self, mesh: &Mesh) {
        let p = mesh.positions();
        for t in mesh.triangles() {
            let [a, b, c] = t.map(|v| self.project(&p[v as usize]));
            let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            if area.abs() <= 1e-12 || area.is_nan() {
                continue;
            }
            let x_lo = a[0].min(b[0]).min(c[0]).floor().max(0.0) as i64;
            let y_lo = a[1].min(b[1]).min(c[1]).floor().max(0.0) as i64;
            let x_hi = (a[0].max(b[0]).max(c[0]).ceil() as i64).min(MAP_SIZE as i64 - 1);
            let y_hi = (a[1].max(b[1]).max(c[1]).ceil() as i64).min(MAP_SIZE as i64 - 1);
            let edge = |p: [f32; 3], q: [f32; 3], x: f32, y: f32| {
                ((q[0] - p[0]) * (y - p[1]) - (q[1] - p[1]) * (x - p[0])) / area
            };
            for y in y_lo..=y_hi {
                for x in x_lo..=x_hi {
                    let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                    let (wa, wb, wc) = (edge(b, c, px, py), edge(c, a, px, py), edge(a, b, px, py));
                    if wa >= 0.0 && wb >= 0.0 && wc >= 0.0 {
                        self.write(x, y, wa * a[2] + wb * b[2] + wc * c[2]);
                    }
                }
            }
        }
    }

    fn splat_strands(&mut self, strands: &Strands) {
        let pos = strands.positions();
        for s in 0..strands.len() {
            let r = strands.points(s);
            for i in r.start..r.end - 1 {
                let (a, b) = (self.project(&pos[i]), self.project(&pos[i + 1]));
                let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
                let steps = (2.0 * len).ceil().max(1.0) as usize;
                for k in 0..=steps {
                    let t = k as f32 / steps as f32;
                    let q = [0, 1, 2].map(|j| a[j] + (b[j] - a[j]) * t);
                    self.write(q[0].floor() as i64, q[1].floor() as i64, q[2]);
                }
            }
        }
    }

    /// Fraction of the key light reaching `p`, in (0, 1], averaged over the `taps` × `taps`
    /// texels nearest to it (2 for hair; more softens the shadows thin strands cast on meshes);
    /// `bias` meters of depth are forgiven (a surface does not shadow itself).
    pub fn light_at(&self, p: &Vector3<f32>, bias: f32, taps: i64) -> f32 {
        let [u, v, d] = self.project(p);
        let x0 = (u - 0.5).floor() as i64 - (taps / 2 - 1);
        let y0 = (v - 0.5).floor() as i64 - (taps / 2 - 1);
        let mut sum = 0.0;
        for y in y0..y0 + taps {
            for x in x0..x0 + taps {
                let inside = (0..MAP_SIZE as i64).contains(&x) && (0..MAP_SIZE as i64).contains(&y);
                if !inside {
                    sum += 1.0;
                    continue;
                }
                let first = self.depth[y as usize * MAP_SIZE + x as usize];
                let behind = (d - first - bias).max(0.0);
                sum += (-behind * self.falloff).exp();
            }
        }
        sum / (taps * taps) as f32
    }

    /// Depth bias for a receiver: a few texels, meters.
    pub fn texel_bias(&self, texels: f32) -> f32 {
        texels / self.scale
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A dense sheet of strands along x at z = 0 over a 0.2 m square, lit from +z.
    #[test]
    fn light_falls_exponentially_behind_the_first_hair() {
        let mut positions = Vec::new();
        let mut offsets = vec![0u32];
        for k in 0..400 {
            let y = -0.1 + 0.2 * k as f32 / 399.0;
            positions.push(Vector3::new(-0.1, y, 0.0));
            positions.push(Vector3::new(0.1, y, 0.0));
            offsets.push(positions.len() as u32);
        }
        let strands = Strands::new(&positions, &offsets).unwrap();
        let bounds = Bounds {
            min: Vector3::new(-0.2, -0.2, -0.05),
            max: Vector3::new(0.2, 0.2, 0.05),
        };
        let map = ShadowMap::build(Some(&strands), &[], &bounds, Vector3::z(), 0.01);
        for taps in [2, 6] {
            let above = map.light_at(&Vector3::new(0.0, 0.0, 0.01), 0.0, taps);
            let below = map.light_at(&Vector3::new(0.0, 0.0, -0.02), 0.0, taps);
            assert!((above - 1.0).abs() < 1e-6, "{above}");
            assert!((below - (-2.0f32).exp()).abs() < 1e-3, "{below}");
        }
        // Beside the sheet nothing is in the way.
        let beside = map.light_at(&Vector3::new(0.0, 0.15, -0.02), 0.0, 2);
        assert!((beside - 1.0).abs() < 1e-6, "{beside}");
    }
}
