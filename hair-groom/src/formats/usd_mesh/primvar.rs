//! A USD `Mesh` prim's primvars as values at the corners of its triangles: the painted maps a
//! DCC writes on a scalp (Blender's USD export writes a vertex group `density` as
//! `float[] primvars:density` with `interpolation = "vertex"`).
//!
//! The USD specification (UsdGeomPrimvar, "Interpolation of Geometric Primitive Variables")
//! defines how many values a primvar has and where each applies:
//!
//! | interpolation | values | a triangle's corner takes |
//! |---|---|---|
//! | `constant` (also when unauthored: USD's fallback) | 1 | the value |
//! | `uniform` | one per face | its face's value |
//! | `vertex`, `varying` | one per point | its point's value |
//! | `faceVarying` | one per face corner (`faceVertexIndices` order) | its face corner's value |
//!
//! An indexed primvar (`primvars:NAME:indices`) holds the element count in its indices, each
//! naming one of the values. On a polygon mesh `vertex` and `varying` differ only for
//! subdivision surfaces (linear vs limit-surface interpolation); hairsys samples the polygon
//! mesh itself, so both blend linearly. A triangle's corners are its face's corners in the fan
//! order of [`UsdMeshSource::triangles`], so a value blended with a hair root's barycentric
//! weights is the linear interpolation over the triangle the root lies in — on a `vertex`
//! primvar exactly what the artist painted at the vertices, across a `faceVarying` seam each
//! face's own values.
//!
//! Scalar types (`float`, `double`, `half`, `int`) give their value; 3-vectors (`color3f`,
//! `float3`, `vector3f`, … and their `double`/`half` forms) one component chosen by the caller.
//! A primvar whose element count does not fit its interpolation, an index out of range, an
//! `elementSize` other than 1, a non-finite value or a missing primvar (the error lists the
//! prim's primvars) is an error naming the file, the prim and the primvar.

use openusd::sdf;
use openusd::usd::TimeCode;

use super::super::usd::{interpolation, kind, value_at, PrimError};
use super::{fans, wind, UsdMeshSource};
use crate::error::{FileLocation, GroomError};
use crate::formats::bad;

/// How a primvar's values spread over a mesh (USD's `interpolation` metadata).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PrimvarInterpolation {
    /// One value for the whole mesh.
    Constant,
    /// One value per face.
    Uniform,
    /// One value per point, blended linearly across faces.
    Vertex,
    /// One value per point (linear on a polygon mesh: the same as `Vertex` here).
    Varying,
    /// One value per face corner.
    FaceVarying,
}

impl PrimvarInterpolation {
    /// USD's token for it.
    pub fn token(self) -> &'static str {
        match self {
            Self::Constant => "constant",
            Self::Uniform => "uniform",
            Self::Vertex => "vertex",
            Self::Varying => "varying",
            Self::FaceVarying => "faceVarying",
        }
    }
}

/// One primvar's values at the three corners of every triangle of
/// [`UsdMeshSource::triangles`], in that order (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct CornerValues {
    /// The primvar's interpolation.
    pub interpolation: PrimvarInterpolation,
    /// Per triangle, the value at its three corners, in its winding.
    pub values: Vec<[f32; 3]>,
}

impl UsdMeshSource {
    /// The primvar `name` (`"density"` reads `primvars:density`; a leading `primvars:` is
    /// accepted) at time code `time` (its default value when it is not time-sampled), at the
    /// corners of every triangle. `component` picks the component of a 3-vector primvar
    /// (0, 1 or 2; `None`: 0); a scalar primvar takes `None` or `Some(0)`. Errors name the file,
    /// the prim, the primvar and the fix (see the module docs).
    pub fn primvar(
        &self,
        name: &str,
        component: Option<usize>,
        time: f64,
    ) -> Result<CornerValues, GroomError> {
        let name = name.strip_prefix("primvars:").unwrap_or(name);
        let attr = format!("primvars:{name}");
        super::super::usd::guarded(&self.path, || {
            self.read_primvar(&attr, component, TimeCode::new(time))
                .map_err(|m| {
                    bad(
                        &self.path,
                        FileLocation::File,
                        format!("prim {} {attr}: {m}", self.prim),
                    )
                })
        })
    }

    /// The time codes at which the primvar `name` (or its `:indices`) has time samples, sorted
    /// and without repeats; empty when it has none (a default value only). A primvar not on
    /// the prim has none. Errors name the file, the prim and the primvar.
    pub fn primvar_sample_times(&self, name: &str) -> Result<Vec<f64>, GroomError> {
        let name = name.strip_prefix("primvars:").unwrap_or(name);
        let attr = format!("primvars:{name}");
        super::super::usd::guarded(&self.path, || {
            let prim = self.stage.prim(self.prim.as_str());
            let mut times = Vec::new();
            for a in [attr.clone(), format!("{attr}:indices")] {
                times.extend(prim.attribute(&a).time_sample_times().map_err(|e| {
                    bad(
                        &self.path,
                        FileLocation::File,
                        format!(
                            "prim {} {a}: cannot read its time samples: {e:#}",
                            self.prim
                        ),
                    )
                })?);
            }
            times.sort_by(f64::total_cmp);
            times.dedup();
            Ok(times)
        })
    }

    fn read_primvar(
        &self,
        attr: &str,
        component: Option<usize>,
        time: TimeCode,
    ) -> Result<CornerValues, PrimError> {
        let prim = self.stage.prim(self.prim.as_str());
        let Some(value) = value_at(&prim, attr, time)? else {
            let mut primvars: Vec<String> = prim
                .property_names()
                .map_err(|error| PrimError::Properties { error })?
                .iter()
                .map(|t| t.as_str().to_string())
                .filter(|n| n.starts_with("primvars:") && !n.ends_with(":indices"))
                .collect();
            primvars.sort();
            return Err(PrimError::NoPrimvar { primvars });
        };
        let values = components(value, component)?;
        if let Some(index) = values.iter().position(|v| !v.is_finite()) {
            return Err(PrimError::NonFiniteValue {
                index,
                value: values[index],
            });
        }
        let element_size = prim
            .attribute(attr)
            .get_metadata::<sdf::Value>("elementSize")
            .ok()
            .flatten();
        match element_size {
            None | Some(sdf::Value::Int(1)) => {}
            Some(other) => {
                return Err(PrimError::ElementSize {
                    found: format!("{other:?}"),
                })
            }
        }
        let indices = match value_at(&prim, &format!("{attr}:indices"), time)? {
            Some(sdf::Value::IntVec(ix)) => Some(ix),
            Some(other) => {
                return Err(PrimError::PrimvarIndices {
                    attr: attr.to_string(),
                    found: kind(&other),
                })
            }
            None => None,
        };
        let interp = match interpolation(&prim, attr).as_deref() {
            None | Some("constant") => PrimvarInterpolation::Constant,
            Some("uniform") => PrimvarInterpolation::Uniform,
            Some("vertex") => PrimvarInterpolation::Vertex,
            Some("varying") => PrimvarInterpolation::Varying,
            Some("faceVarying") => PrimvarInterpolation::FaceVarying,
            Some(other) => {
                return Err(PrimError::Interpolation {
                    found: other.to_string(),
                })
            }
        };
        let (wanted, per) = match interp {
            PrimvarInterpolation::Constant => (1, "value (constant)"),
            PrimvarInterpolation::Uniform => (self.face_counts.len(), "faces (uniform)"),
            PrimvarInterpolation::Vertex | PrimvarInterpolation::Varying => {
                (self.point_count, "points (vertex/varying)")
            }
            PrimvarInterpolation::FaceVarying => {
                (self.face_indices.len(), "face corners (faceVarying)")
            }
        };
        let elements = indices.as_ref().map_or(values.len(), Vec::len);
        if elements != wanted {
            return Err(PrimError::ElementCount {
                elements,
                indexed: indices.is_some(),
                wanted,
                per,
                unauthored: interpolation(&prim, attr).is_none(),
                faces: self.face_counts.len(),
                points: self.point_count,
                corners: self.face_indices.len(),
            });
        }
        let element = |i: usize| -> Result<f32, PrimError> {
            let j = match &indices {
                Some(ix) => {
                    let index = ix[i];
                    usize::try_from(index)
                        .ok()
                        .filter(|&j| j < values.len())
                        .ok_or_else(|| PrimError::PrimvarIndex {
                            attr: attr.to_string(),
                            element: i,
                            index,
                            values: values.len(),
                        })?
                }
                None => i,
            };
            Ok(values[j])
        };
        let corner_element = |face: usize, corner: usize| -> usize {
            match interp {
                PrimvarInterpolation::Constant => 0,
                PrimvarInterpolation::Uniform => face,
                PrimvarInterpolation::Vertex | PrimvarInterpolation::Varying => {
                    self.face_indices[corner] as usize
                }
                PrimvarInterpolation::FaceVarying => corner,
            }
        };
        let mut out = Vec::with_capacity(self.triangles.len());
        for (face, corners) in fans(&self.face_counts) {
            let [a, b, c] = wind(corners, self.flip);
            out.push([
                element(corner_element(face, a))?,
                element(corner_element(face, b))?,
                element(corner_element(face, c))?,
            ]);
        }
        Ok(CornerValues {
            interpolation: interp,
            values: out,
        })
    }
}

/// The values of a primvar's value: scalars as they are, one `component` of 3-vectors.
fn components(value: sdf::Value, component: Option<usize>) -> Result<Vec<f32>, PrimError> {
    let scalar = |values: Vec<f32>| -> Result<Vec<f32>, PrimError> {
        match component {
            None | Some(0) => Ok(values),
            Some(component) => Err(PrimError::NoComponent { component }),
        }
    };
    let c = component.unwrap_or(0);
    let pick = |len: usize, get: &dyn Fn(usize) -> [f32; 3]| -> Result<Vec<f32>, PrimError> {
        if c > 2 {
            return Err(PrimError::Component { component: c });
        }
        Ok((0..len).map(|i| get(i)[c]).collect())
    };
    match value {
        sdf::Value::Float(x) => scalar(vec![x]),
        sdf::Value::Double(x) => scalar(vec![x as f32]),
        sdf::Value::Half(x) => scalar(vec![x.to_f32()]),
        sdf::Value::Int(x) => scalar(vec![x as f32]),
        sdf::Value::FloatVec(v) => scalar(v),
        sdf::Value::DoubleVec(v) => scalar(v.into_iter().map(|x| x as f32).collect()),
        sdf::Value::HalfVec(v) => scalar(v.into_iter().map(|x| x.to_f32()).collect()),
        sdf::Value::IntVec(v) => scalar(v.into_iter().map(|x| x as f32).collect()),
        sdf::Value::Vec3f(p) => pick(1, &|_| [p.x, p.y, p.z]),
        sdf::Value::Vec3d(p) => pick(1, &|_| [p.x as f32, p.y as f32, p.z as f32]),
        sdf::Value::Vec3fVec(v) => pick(v.len(), &|i| [v[i].x, v[i].y, v[i].z]),
        sdf::Value::Vec3dVec(v) => {
            pick(v.len(), &|i| [v[i].x as f32, v[i].y as f32, v[i].z as f32])
        }
        sdf::Value::Vec3hVec(v) => pick(v.len(), &|i| {
            [v[i].x.to_f32(), v[i].y.to_f32(), v[i].z.to_f32()]
        }),
        other => Err(PrimError::ValueType {
            found: kind(&other),
        }),
    }
}

#[cfg(test)]
mod tests;
