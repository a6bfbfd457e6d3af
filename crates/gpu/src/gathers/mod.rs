//! The methods that replace the separable kernel by a gather per pixel: over the lit surface
//! found through the lights' maps ([`disc_gather`]) with the directional dipole ([`dipole`]) or
//! the Monte Carlo BSSRDF ([`surface_gather`]), and Maisch & Ropinski's screen-space area
//! gather ([`area_gather`]).

pub mod area_gather;
pub mod dipole;
pub mod disc_gather;
pub mod surface_gather;

use crate::error::Result;
use crate::frame::context::Gpu;
use crate::frame::recording::Recording;
use crate::frame::target::Target;
use crate::passes::Pass;
use dipole::DipoleSetup;
use disc_gather::DiscPipelines;
use surface_gather::SurfaceGatherSetup;

/// A model the disc gather integrates over the lit surface.
#[derive(Clone, Copy)]
pub(crate) enum DiscModel<'a> {
    /// The directional dipole.
    Dipole(&'a DipoleSetup),
    /// The material's own Monte Carlo BSSRDF.
    Surface(&'a SurfaceGatherSetup),
}

impl Pass for DiscPipelines {
    /// The target and the model.
    type Input<'a> = (&'a Target<'a>, DiscModel<'a>);
    /// Nothing: the gather adds π·L_o into the target's scattered light.
    type Output = ();

    /// The pipelines compile on their first frame (a renderer that never gathers never pays).
    fn new(_: &Gpu) -> DiscPipelines {
        DiscPipelines::default()
    }

    fn encode(&self, rec: &mut Recording, (target, model): Self::Input<'_>) -> Result<()> {
        match model {
            DiscModel::Dipole(setup) => dipole::encode(rec, target, setup, self),
            DiscModel::Surface(setup) => surface_gather::encode(rec, target, setup, self),
        }
    }
}
