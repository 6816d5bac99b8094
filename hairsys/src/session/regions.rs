//! A session's `[[regions]]` between frames: read a region's parameters, change its
//! springs, damping and drag for the frames to come (an animated region), see
//! [`crate::scene::regions`].
//!
//! A change goes to the solver as new per-strand factors of the current `[physics]`
//! (`hair_core::MassSpringSolver::set_strand_scales`); like [`Session::params_mut`] it keeps the
//! substep, so a region made stiffer than `substeps = "auto"` was chosen for may make the next step
//! unstable, which that step reports. Mass and radius are fixed when the scene is built.
//! [`Session::restore`] puts back the solver's factors of the snapshot's frame, but
//! [`Session::region_params`] keeps reporting the values last set (the region table is not part
//! of a snapshot).

use crate::error::{Error, Result};
use crate::scene::regions::{check_params, RegionParams};
use crate::Session;

impl Session {
    /// The names of the scene's `[[regions]]`, in file order (empty for a session a host
    /// assembled).
    pub fn region_names(&self) -> Vec<String> {
        self.animation.as_ref().map_or_else(Vec::new, |a| {
            a.sim
                .regions
                .regions
                .iter()
                .map(|r| r.name.clone())
                .collect()
        })
    }

    /// Region `name`'s parameters as last set (the scene's, or [`Session::set_region_params`]'s).
    pub fn region_params(&self, name: &str) -> Result<RegionParams> {
        let regions = &self.region_table()?.regions;
        regions
            .iter()
            .find(|r| r.name == name)
            .map(|r| r.params)
            .ok_or_else(|| self.unknown_region(name))
    }

    /// The strands of region `name` (indices into [`Session::strands`]), increasing.
    pub fn region_strands(&self, name: &str) -> Result<Vec<usize>> {
        let regions = &self.region_table()?.regions;
        regions
            .iter()
            .find(|r| r.name == name)
            .map(|r| r.strands.clone())
            .ok_or_else(|| self.unknown_region(name))
    }

    /// Gives region `name` the parameters `params` from the next frame on: `[physics]` keys in
    /// their units (None = the scene's `[physics]` value), checked as in the scene file. Mass
    /// and radius factors cannot change after the scene is built (give the scene's). Where
    /// regions overlap the later one in the file still wins.
    pub fn set_region_params(&mut self, name: &str, params: RegionParams) -> Result<()> {
        let unknown = self.unknown_region(name);
        let argument = format!("region \"{name}\"");
        let current = *self
            .solver
            .mass_spring()
            .ok_or_else(|| Error::argument(&argument, "regions are for the mass-spring model"))?
            .params();
        let table = &mut self
            .animation
            .as_mut()
            .ok_or_else(|| Error::argument(&argument, "this session has no scene regions"))?
            .sim
            .regions;
        let mut changed = table.clone();
        let region = changed.get_mut(name).ok_or(unknown)?;
        if (params.mass_scale, params.radius_scale)
            != (region.params.mass_scale, region.params.radius_scale)
        {
            return Err(Error::argument(
                &argument,
                "mass_scale and radius_scale are fixed when the scene is built; give the \
                 scene's values",
            ));
        }
        check_params(&params, &current, &argument)
            .map_err(|e| Error::argument(&argument, e.to_string()))?;
        region.params = params;
        let scales = changed
            .scales(&current, self.strands.len())
            .map_err(|e| Error::argument(&argument, e.to_string()))?;
        let count = self.strands.len();
        let solver = self.solver.mass_spring_mut().expect("checked above");
        solver
            .set_strand_scales(scales, count)
            .map_err(|e| Error::argument(&argument, e.to_string()))?;
        *table = changed;
        Ok(())
    }

    fn region_table(&self) -> Result<&crate::scene::regions::Regions> {
        self.animation
            .as_ref()
            .map(|a| &a.sim.regions)
            .ok_or_else(|| Error::argument("region", "this session has no scene regions"))
    }

    fn unknown_region(&self, name: &str) -> Error {
        Error::argument(
            format!("region \"{name}\""),
            format!(
                "is not one of the scene's regions {:?}; fix the name",
                self.region_names()
            ),
        )
    }
}
