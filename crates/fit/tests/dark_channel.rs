//! A channel that does not scatter (σs = 0, as wine's green and blue) returns no diffuse light:
//! Rd ≡ 0. Physics says what its kernel is: nothing spreads, so its normalized kernel is the
//! identity and its weight, the channel's reflectance, is 0. Every model gives that; the lit
//! channels are fitted exactly as without the dark ones; nothing is NaN; a profile dark in every
//! channel is refused, naming Rd.

use fit::engine::BurleyProfileFit;
use fit::evaluate::{MODELS, evaluate};
use fit::metrics::ImageSize;
use fit::select::Judge;
use fit::{KernelModel, Profile, ground_truths};

/// Wine-like: the red channel scatters (an exponential-tailed diffusion profile, 1/r at the
/// centre as single scattering), the others do not, unless `lit` says so.
fn profile(lit: [bool; 3]) -> Profile {
    Profile::from_fn(0.01, 60, |c, r| {
        if lit[c] {
            0.3 * (-r / 0.08).exp() / r
        } else {
            0.0
        }
    })
}

#[test]
fn a_dark_channel_spreads_nothing_in_every_model() {
    let dark = profile([true, false, false]);
    dark.validate().unwrap();
    let truths = ground_truths(&dark);
    for c in [1, 2] {
        assert!(truths[c].is_delta(), "channel {c}");
    }
    assert!(!truths[0].is_delta());
    // The same red channel beside two lit ones: what the per-channel models fit to it.
    let lit = profile([true, true, true]);
    for model in MODELS {
        if matches!(model, KernelModel::Burley { radial: true }) {
            continue; // not separable: evaluated below
        }
        let fitted = model.fit(&dark, "wine").unwrap();
        for c in [1, 2] {
            let k = fitted.channels[c].to_dense();
            assert!(k.is_delta(), "{model}: channel {c} is not the identity");
        }
        // The skin model's fit is joint over the channels (one set of Gaussians), the others
        // per channel: their red kernel does not see the dark channels.
        if !matches!(model, KernelModel::Skin(_)) {
            let alone = model.fit(&lit, "wine").unwrap();
            assert_eq!(
                fitted.channels[0].to_dense(),
                alone.channels[0].to_dense(),
                "{model}: the dark channels changed the red kernel"
            );
        }
    }
}

#[test]
fn evaluation_and_engine_fits_of_a_dark_channel_are_exact_and_finite() {
    let p = profile([true, false, false]);
    let e = evaluate(
        &p,
        "wine",
        ImageSize {
            size: 64,
            max_half: 32,
        },
    )
    .unwrap();
    for row in &e.rows {
        let images = row.image_rms.iter().map(|(_, v)| *v);
        for v in [row.kernel_rms, row.kernel_rms_normalized, row.l1_error]
            .into_iter()
            .chain(images.clone())
        {
            assert!(v.is_finite(), "{} channel {}: {v}", row.model, row.channel);
        }
        if row.channel > 0 {
            // The identity against the identity: no error but rounding in the image test.
            assert_eq!(row.kernel_rms, 0.0, "{}", row.model);
            for v in images {
                assert!(v < 1e-12, "{}: {v}", row.model);
            }
        }
    }
    let fit = BurleyProfileFit::new(&p, &Judge::new(&p));
    assert_eq!(fit.dark, [false, true, true]);
    assert_eq!(fit.albedo[1], 0.0);
    // The dark channels do not set the engine's distance scale: they take the lit one's length.
    assert_eq!(fit.d_cm[1], fit.d_cm[0]);
    assert!(fit.d_cm[0].is_finite() && fit.d_cm[0] > 0.0);
    assert!(
        fit.kernel_rms_rel
            .iter()
            .chain(&fit.image_rms)
            .all(|v| v.is_finite())
    );
}

#[test]
fn a_profile_dark_in_every_channel_is_refused_naming_rd() {
    let e = profile([false; 3]).validate().unwrap_err().to_string();
    assert!(e.contains("Rd") && e.contains("every channel"), "{e}");
}
