//! `ShaderKernel::tap_error`: sampling a fitted kernel into taps costs image error, which falls
//! as the taps grow (5 against 65 taps on Skin1's pre-integration).

mod common;

use fit::KernelModel;
use fit::taps::{ShaderKernel, TapSpec};

#[test]
fn more_taps_come_closer_to_the_full_kernel() {
    let (p, _) = common::skin1_quick();
    let truths: Vec<_> = fit::ground_truths(&p);
    let fitted = KernelModel::Preint.fit_truths(&truths, "skin1").unwrap();
    let error = |taps| {
        let spec = TapSpec {
            taps,
            ..TapSpec::default()
        };
        ShaderKernel::from_fitted(&fitted, "skin1", spec)
            .unwrap()
            .tap_error(&p, &fitted)
    };
    let (few, many) = (error(5), error(65));
    for c in 0..3 {
        assert!(few[c].is_finite() && many[c] >= 0.0, "{few:?} {many:?}");
        assert!(
            many[c] < 0.5 * few[c],
            "channel {c}: 65 taps {} vs 5 taps {}",
            many[c],
            few[c]
        );
    }
}
