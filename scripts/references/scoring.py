"""Scoring one image against Mitsuba's reference on 2×2 pixel blocks: the noise-corrected RMSE
with its standard error, the energy ratio per channel, the spatial part left by each channel's
best global factor, SSIM, paired comparisons of two models block by block, the calibration test,
and the blocks a comparison uses (those that see an SSS shape, silhouettes excluded). Errors are
relative to the reference's mean over the compared blocks (a fraction, not %)."""

import math
from dataclasses import dataclass

import numpy as np

def blocks(img, k=2):
    """k×k block averages."""
    h, w, c = img.shape
    return img[: h - h % k, : w - w % k].reshape(h // k, k, w // k, k, c).mean((1, 3))


def ssim(a, b, win=7):
    """Mean SSIM of two luminance images with a win×win box window (Wang et al. 2004)."""
    def box(x):
        c = np.pad(x, ((1, 0), (1, 0))).cumsum(0).cumsum(1)
        return (c[win:, win:] - c[:-win, win:] - c[win:, :-win] + c[:-win, :-win]) / win**2
    L = max(a.max(), b.max(), 1e-12)
    c1, c2 = (0.01 * L) ** 2, (0.03 * L) ** 2
    ma, mb = box(a), box(b)
    va, vb, cov = box(a * a) - ma**2, box(b * b) - mb**2, box(a * b) - ma * mb
    s = ((2 * ma * mb + c1) * (2 * cov + c2)) / ((ma**2 + mb**2 + c1) * (va + vb + c2))
    return float(s.mean())


def measure(o2, r2, d2, mask, mean, do2=None):
    """One image against a reference on 2×2 blocks (o2, r2: block images; d2: the difference of
    the reference's two half-budget renders; mask: the blocks compared; mean: the reference's mean
    there; do2: the same difference for an image that is itself a Monte Carlo estimate, the surface
    gathers). Per block, (o − r̄)² − (r₁ − r₂)²/4 − (o₁ − o₂)²/4 estimates the squared error
    between the noiseless images without bias (var(r̄) = E(r₁ − r₂)²/4): the noise-corrected
    MSE is its mean, with the standard error of that mean, and "resolved" says whether it lies
    more than 3 standard errors above 0. Returns the per-block estimates (for paired comparisons)
    and the summary numbers."""
    noise = d2[mask] ** 2 / 4 + (0 if do2 is None else do2[mask] ** 2 / 4)
    per = ((o2 - r2)[mask] ** 2 - noise).mean(1)
    rmse = float(np.sqrt(((o2 - r2)[mask] ** 2).mean()) / mean)
    mse_c, mse_se = float(per.mean()), float(per.std(ddof=1) / math.sqrt(per.size))
    mean = float(mean)
    rmse_c = math.sqrt(max(mse_c, 0.0)) / mean
    # SE of √MSE by the delta method where the MSE is resolved from 0; else the bound √(3 SE).
    rmse_c_se = mse_se / (2 * math.sqrt(mse_c)) / mean if mse_c > 3 * mse_se else math.sqrt(3 * mse_se) / mean
    # Energy per channel over the blocks, with its standard error from the reference's noise
    # (var Σr̄ = Σ(r₁ − r₂)²/4): what a global factor explains.
    rs = r2[mask].sum(0)
    energy = [float(o2[mask][:, c].sum() / rs[c]) for c in range(3)]
    energy_se = [float(e * math.sqrt((d2[mask][:, c] ** 2 / 4).sum()) / rs[c]) for c, e in enumerate(energy)]
    return per, {"rmse_rel": rmse, "rmse_noise_corrected": rmse_c, "rmse_noise_corrected_se": rmse_c_se,
                 "resolved": bool(mse_c > 3 * mse_se), "energy_ratio": energy, "energy_ratio_se": energy_se}


def score(o2, r2, d2, mask, mean, noise2=None):
    """A model's row of the comparison: measure()'s numbers, plus the attribution (the error left
    once each channel is scaled by its best global factor, by least squares s = Σ o·r̄ / Σ o²,
    which the noise term does not change: the spatial structure; and the share of the
    noise-corrected MSE that factor explains) and SSIM on luminance. noise2: the difference of
    the model's own two half-budget renders, where it is a Monte Carlo estimate. Returns the
    per-block estimates (for paired rankings) and the row."""
    per, row = measure(o2, r2, d2, mask, mean, noise2)
    o, r = o2[mask], r2[mask]
    scale = [float((o[:, c] * r[:, c]).sum() / max((o[:, c] ** 2).sum(), 1e-300)) for c in range(3)]
    _, flat = measure(o2 * np.array(scale), r2, d2, mask, mean,
                      None if noise2 is None else noise2 * np.array(scale))
    row["best_scale"] = scale
    row["rmse_spatial"] = flat["rmse_noise_corrected"]
    row["rmse_spatial_se"] = flat["rmse_noise_corrected_se"]
    total = row["rmse_noise_corrected"] ** 2
    row["energy_share"] = 1 - flat["rmse_noise_corrected"] ** 2 / total if total > 0 else float("nan")
    lum = lambda x: x @ np.array([0.2126, 0.7152, 0.0722])
    row["ssim"] = ssim(lum(o2), lum(r2))
    # Structural dissimilarity, as Maisch & Ropinski report: (1 − SSIM)/2.
    row["dssim"] = (1 - row["ssim"]) / 2
    return per, row


def paired(per_a, per_b):
    """Is a model closer to the truth than another? Paired over blocks (their per-block
    estimates from score()): True/False where the difference of noise-corrected MSEs exceeds 3
    standard errors, else None (undecided)."""
    diff = per_a - per_b
    m, se = diff.mean(), diff.std(ddof=1) / math.sqrt(diff.size)
    return None if abs(m) <= 3 * se else bool(m < 0)


# Calibration tolerance: `sss render --no-sss` against Mitsuba's direct lighting of the same
# opaque Lambertian surfaces, silhouettes masked. Rasterized shadow maps and Mitsuba's exact
# visibility differ along shadow edges by up to a texel, so agreement "within the noise" is
# allowed 2 % of the mean in noise-corrected RMSE (the kernel models differ from each other by
# 1–10 %), and every channel's energy within 1 % (or 3 standard errors, if larger).
CAL_RMSE, CAL_ENERGY = 0.02, 0.01


def calibrated(m):
    """Does a calibration measurement pass?"""
    return bool(m["rmse_noise_corrected"] <= CAL_RMSE and all(
        abs(e - 1) <= max(CAL_ENERGY, 3 * se) for e, se in zip(m["energy_ratio"], m["energy_ratio_se"])))


@dataclass
class Comparison:
    """The blocks one comparison is scored on: 2×2 block images [h/2 × w/2 × 3] of linear
    radiance, and the mask and scale every error uses."""
    ref: np.ndarray        # Mitsuba's reference, the mean of its two halves [h × w × 3]
    r2: np.ndarray         # the reference on 2×2 blocks
    d2: np.ndarray         # the difference of its two halves on 2×2 blocks (its noise)
    o2s: dict              # each model's image on 2×2 blocks, by label
    sil: np.ndarray        # blocks with a silhouette or crease pixel [h/2 × w/2], bool
    mask: np.ndarray       # the blocks compared: they see an SSS shape, no silhouette [h/2 × w/2], bool
    mean: float            # the reference's mean over the compared blocks
    silhouette_fraction: float  # the share of the blocks that see an SSS shape excluded as silhouettes
    noise: float           # the reference's noise per 2×2 block, relative to `mean`


def compare_blocks(refs, renders):
    """The Comparison of our renders (ours.Renders) against Mitsuba's (mitsuba3.References)."""
    # Errors on 2×2 pixel blocks (Mitsuba's noise averages down, the scattering does not), over
    # the blocks that see an SSS shape, silhouettes excluded (a block with a pixel within one
    # pixel of a boundary between shapes: anti-aliased in Mitsuba, not in ours), relative to the
    # reference's mean there. The blocks are the scene's geometry alone: the same whichever
    # models are compared and however noisy the reference (a mask of the blocks that any image
    # lights grew with the models and with Mitsuba's fireflies in the dark).
    ref = 0.5 * (refs.ref_a + refs.ref_b)
    r2, d2 = blocks(ref), blocks(refs.ref_a) - blocks(refs.ref_b)
    o2s = {k: blocks(v) for k, v in renders.images.items()}
    seen = blocks(refs.cover).sum(2) > 0
    sil = blocks(refs.edge[:, :, None].astype(np.float64))[:, :, 0] > 0
    mask = seen & ~sil
    silhouette_fraction = float((seen & sil).sum() / seen.sum())
    mean = r2[mask].mean()
    noise = float(np.sqrt((d2[mask] ** 2 / 4).mean()) / mean)
    return Comparison(ref, r2, d2, o2s, sil, mask, mean, silhouette_fraction, noise)


@dataclass
class Calibration:
    """The calibration of one comparison: our --no-sss render against Mitsuba's direct light on
    the same opaque Lambertian surfaces, and the negative control."""
    cal: dict              # measure()'s numbers of the calibration render
    control: dict          # measure()'s numbers of the negative control (albedo × 0.8)
    passes: bool           # whether the calibration passes (calibrated())
    control_rejected: bool  # whether the negative control fails the same test
    interreflection: list  # Mitsuba's all bounces over direct light per channel (Lambertian surfaces)
    mean: float            # the mean of Mitsuba's direct light over the calibration's blocks


def calibrate(refs, renders, sil):
    """The Calibration of our renders (ours.Renders) against Mitsuba's (mitsuba3.References),
    silhouette blocks `sil` excluded."""
    cal_a, cal_b = refs.cal_a, refs.cal_b
    # Calibration: our Lambertian image against Mitsuba's direct light on the same opaque
    # surfaces, on the blocks either lights (camera, light and geometry are calibrated where
    # there is direct light; blocks in shadow are 0 in both); and the deliberately wrong render
    # against it.
    c2, dc2 = blocks(0.5 * (cal_a + cal_b)), blocks(cal_a) - blocks(cal_b)
    l2 = blocks(renders.lambertian)
    cal_mask = (c2.sum(2) > 0) | (l2.sum(2) > 0)
    cal_mask &= ~sil
    cal_mean = c2[cal_mask].mean()
    _, cal = measure(l2, c2, dc2, cal_mask, cal_mean)
    _, control = measure(blocks(renders.wrong), c2, dc2, cal_mask, cal_mean)
    cal_ok, control_rejected = calibrated(cal), not calibrated(control)
    # Light that reaches the camera after more than one bounce between the scene's surfaces: no
    # screen-space model adds it.
    interreflection = [float(blocks(refs.gi)[cal_mask][:, c].sum() / c2[cal_mask][:, c].sum()) for c in range(3)]
    return Calibration(cal, control, cal_ok, control_rejected, interreflection, cal_mean)


def print_calibration(setup, comparison, calibration):
    """Prints the compared blocks, the reference's noise, the calibration, the negative control
    and the interreflections."""
    cal, control = calibration.cal, calibration.control
    print(f"  {setup.name}, {setup.material}: {comparison.mask.sum()} blocks compared, silhouettes "
          f"{100 * comparison.silhouette_fraction:.1f}% of the lit blocks (excluded)")
    print(f"  reference noise (2×2 blocks, mean of two seeds): {100 * comparison.noise:.2f}% of the mean")
    print(f"  calibration (--no-sss against Mitsuba's direct light on Lambertian surfaces): noise-corrected "
          f"RMSE {100 * cal['rmse_noise_corrected']:.2f} ± {100 * cal['rmse_noise_corrected_se']:.2f}% "
          f"(raw {100 * cal['rmse_rel']:.2f}%), energy "
          + "/".join(f"{e:.4f}" for e in cal["energy_ratio"]) + f": {'passes' if calibration.passes else 'FAILS'} "
          f"(≤ {100 * CAL_RMSE:.0f}%, energy within {100 * CAL_ENERGY:.0f}%)")
    print(f"  negative control (albedo × 0.8): energy " + "/".join(f"{e:.3f}" for e in control["energy_ratio"])
          + f", RMSE {100 * control['rmse_noise_corrected']:.1f}%: "
          + ("rejected" if calibration.control_rejected else "NOT REJECTED"))
    print("  interreflections (all bounces / direct, Lambertian): "
          + "/".join(f"{e:.4f}" for e in calibration.interreflection))


def score_models(comparison, gather_noise):
    """Every model's row (score()) on a Comparison, printed: the rows, and per label the
    per-block estimates as they are and with each channel at its best factor (for paired
    rankings). gather_noise: the surface gathers' own noise on 2×2 blocks, by label."""
    c = comparison
    rows, per, per_spatial = [], {}, {}
    for label, o2 in c.o2s.items():
        per[label], row = score(o2, c.r2, c.d2, c.mask, c.mean, gather_noise.get(label))
        # The same per block once each channel is scaled by its best factor: the structure.
        scale, noise2 = np.array(row["best_scale"]), gather_noise.get(label)
        per_spatial[label], _ = measure(o2 * scale, c.r2, c.d2, c.mask, c.mean,
                                        None if noise2 is None else noise2 * scale)
        rows.append({"model": label, **row})
        e = row["energy_ratio"]
        print(f"  {label:<29} noise-corrected RMSE {100 * row['rmse_noise_corrected']:5.2f} ± "
              f"{100 * row['rmse_noise_corrected_se']:4.2f}% (raw {100 * row['rmse_rel']:5.2f}%; "
              f"{100 * row['rmse_spatial']:5.2f}% with the best factor per channel), "
              f"DSSIM {row['dssim']:.4f}, energy {e[0]:.3f}/{e[1]:.3f}/{e[2]:.3f}", flush=True)
    return rows, per, per_spatial
