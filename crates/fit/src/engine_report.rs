//! What an engine gets for a material (`sss engine-params`, Python's `sss.engine_params`): the
//! engine's fields, for Blender also the Random Walk fields, the Christensen–Burley profile
//! fitted to the Monte Carlo profile with what it costs, and the best separable kernel under a
//! budget for comparison.

use serde::Serialize;

use crate::engine::{BurleyProfileFit, Engine, EngineParams, burley_engine, openpbr, random_walk};
use crate::error::Result;
use crate::profile::Profile;
use crate::select::{Budget, Judge};

/// The best separable kernel under a budget, as the report names it.
#[derive(Clone, Debug, Serialize)]
pub struct BestSeparable {
    /// The model as fitted, e.g. `svd2`.
    pub model: String,
    /// The budget, PASSESxTAPS.
    pub budget: String,
    /// Image RMS per channel on the test signals (images in [0, 1]).
    pub image_rms: [f64; 3],
}

/// A material's parameters for one engine and what they cost.
#[derive(Clone, Debug, Serialize)]
pub struct EngineReport {
    /// The material's name.
    pub material: String,
    /// The engine.
    pub engine: Engine,
    /// The engine's fields: Burley's fit in its units, or OpenPBR's exact medium.
    pub params: EngineParams,
    /// Blender only: the Random Walk fields that make Cycles trace the material's own σa, σs
    /// and g (Blender 4.0–5.0's remap inverted).
    pub random_walk: Option<EngineParams>,
    /// The Christensen–Burley profile fitted to the Monte Carlo profile, with its errors.
    pub burley_fit: BurleyProfileFit,
    /// The best separable kernel under the budget.
    pub best_separable: BestSeparable,
}

impl EngineReport {
    /// Fits and scores everything for material `m` (named `slug`) with Monte Carlo profile `p`.
    pub fn new(
        p: &Profile,
        m: &mc::Material,
        slug: &str,
        engine: Engine,
        budget: Budget,
    ) -> Result<Self> {
        let judge = Judge::new(p);
        let fit = BurleyProfileFit::new(p, &judge);
        let best = judge.rank(budget, slug)?.swap_remove(0);
        let params = match engine {
            Engine::OpenPbr => openpbr(m),
            e => burley_engine(e, &fit).expect("every engine but OpenPBR maps Burley's fit"),
        };
        Ok(EngineReport {
            material: slug.to_string(),
            engine,
            params,
            // Blender's random walk traces the medium itself: its fields come from the coefficients.
            random_walk: (engine == Engine::Blender).then(|| random_walk(m)),
            burley_fit: fit,
            best_separable: BestSeparable {
                model: best.model.to_string(),
                budget: budget.to_string(),
                image_rms: best.image_rms,
            },
        })
    }

    /// The report as printed: the fields, the Burley fit and, per channel, what the engine's
    /// profile costs against the best separable kernel.
    pub fn text(&self) -> String {
        let slug = &self.material;
        let mut text = self.params.text(slug);
        if let Some(w) = &self.random_walk {
            text += &w.text(slug);
        }
        let (fit, best) = (&self.burley_fit, &self.best_separable);
        text += &format!(
            "Burley fit to the Monte Carlo profile: albedo {:.4?}, d {:.4e}/{:.4e}/{:.4e} cm\n",
            fit.albedo, fit.d_cm[0], fit.d_cm[1], fit.d_cm[2]
        );
        text += "what the engine's profile costs (images in [0, 1]):\n";
        for (c, ch) in mc::CHANNELS.iter().enumerate() {
            text += &format!(
                "  {ch}: Burley kernel RMS {:.1}% of the MC kernel; image RMS Burley {:.2e}, best separable ({}) {:.2e}\n",
                100.0 * fit.kernel_rms_rel[c],
                fit.image_rms[c],
                best.model,
                best.image_rms[c]
            );
        }
        if self.engine == Engine::OpenPbr {
            text += "  (OpenPBR renderers path-trace the medium itself; the Burley line is what a Burley-based real-time approximation of it costs)\n";
        }
        text
    }
}
