//! `fit`: separable subsurface-scattering kernels from radial diffuse reflectance profiles
//! (Freude 2014, chapters 5–6; Jimenez et al. 2015 supplement).
//!
//! Conventions: lengths in cm; profiles Rd(r) in cm⁻²; 2D kernels are sampled on a square grid with
//! the profile's spacing, centred at the origin, and "normalized" means the samples of a channel
//! sum to 1 (thesis §6.2). A separable kernel is a sum of rank-1 terms sᵢ aᵢ(x) aᵢ(y), applied as
//! two 1D passes per term.
//!
//! Main types: [`Profile`] (input), [`Kernel2`] (dense 2D kernel, the ground truth from
//! [`ground_truth`]), [`Separable`] (every model's output); models: [`svd`], [`preint`],
//! [`Guided`], [`Gaussians`]; evaluation: [`metrics`], [`convolve`], [`signals`].
//!
//! ```
//! use fit::{ground_truth, preint, svd, Profile};
//! // An exponential profile, the same in every channel.
//! let p = Profile::from_fn(0.01, 60, |_, r| (-r / 0.1).exp() / r.max(0.005));
//! let k = ground_truth(&p, 0, None);
//! let (a1, _) = svd(&k, 1);
//! let pre = preint(&k);
//! // Eckart–Young: no rank-1 kernel is closer to K in Frobenius norm than SVD rank-1.
//! assert!(fit::metrics::kernel_rms(&k, &a1) <= fit::metrics::kernel_rms(&k, &pre));
//! ```

#![deny(missing_docs)]
// Units are written in brackets as in the papers, [cm⁻¹]; rustdoc would take them for links.
#![allow(rustdoc::broken_intra_doc_links)]
// Per-channel loops index parallel [_; 3] arrays (profile, kernels, colours) by channel.
#![allow(clippy::needless_range_loop)]

pub mod analytic;
pub mod area_table;
pub mod convolve;
pub mod cycles;
pub mod engine;
pub mod engine_report;
mod error;
pub mod evaluate;
pub mod export;
mod gaussians;
mod guided;
pub mod imitation;
mod kernel2d;
pub mod knobs;
mod manual;
pub mod metrics;
mod model;
pub mod pareto;
mod preint;
mod profile;
pub mod profile_compare;
pub mod select;
mod separable;
pub mod signals;
pub mod skin;
mod svd;
pub mod table_profile;
pub mod taps;

pub use analytic::burley::Burley;
pub use error::{FitError, Result};
pub use gaussians::Gaussians;
pub use guided::{Guided, GuidedFit, GuidedStop};
pub use kernel2d::{Kernel2, SUPPORT_EPSILON, cell_ground_truth, ground_truth, ground_truths};
pub use manual::{Manual, WSweep, table_a1};
pub use model::{Family, FittedKernel, KernelModel, ManualParams, SkinParams};
pub use preint::preint;
pub use profile::Profile;
pub use separable::{Separable, Term};
pub use svd::{Eigen, Stop, svd, top_eigen, top_eigen_to};
