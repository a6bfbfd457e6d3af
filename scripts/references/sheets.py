"""What a person looks at: 8-bit PNGs of linear radiance images (tonemapped) and the labelled
comparison sheet (`sheet.png`: every render beside its difference from Mitsuba on one diverging
colour scale)."""

import os

import numpy as np

from references.scoring import blocks

def tonemap(img, exposure):
    """8-bit sRGB [h × w × 3, uint8] of a linear image times `exposure` (1 / radiance), through
    Narkowicz's fit of the ACES filmic curve."""
    x = np.clip(img * exposure, 0, None)
    t = np.clip((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0, 1)
    s = np.where(t <= 0.0031308, 12.92 * t, 1.055 * np.power(t, 1 / 2.4) - 0.055)
    return (s * 255 + 0.5).astype(np.uint8)


def write_png(path, rgb):
    """A small PNG writer (8-bit RGB) without extra dependencies."""
    import struct
    import zlib
    h, w, _ = rgb.shape
    raw = b"".join(b"\x00" + rgb[y].astype(np.uint8).tobytes() for y in range(h))
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def block_means(img, k):
    """An image [h × w] shown as its k×k block means (each block's pixels set to their mean)."""
    if k == 1:
        return img
    h, w = img.shape
    b = blocks(img[:, :, None], k)[:, :, 0]
    out = np.zeros_like(img)
    out[: h - h % k, : w - w % k] = np.repeat(np.repeat(b, k, 0), k, 1)
    return out


def sheet(path, title, panels, diff_range, diff_label="ours − Mitsuba"):
    """One labelled figure of the comparison: `panels` is a list of (label, image, kind), kind
    "rgb" (8-bit RGB, shown as is) or "diff" (ours − reference, mean of R, G, B, as a fraction of
    the reference's mean), four panels per row under `title`; every difference on one diverging
    scale of ±`diff_range` with its colour bar, which names the difference (`diff_label`)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    cols = 4
    rows = (len(panels) + cols - 1) // cols
    h, w = panels[0][1].shape[:2]
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 3.2 * h / w * rows + 1.6),
                             squeeze=False, layout="constrained")
    shown = None
    for ax, (label, img, kind) in zip(axes.flat, panels):
        if kind == "diff":
            shown = ax.imshow(100 * img, cmap="RdBu_r", vmin=-100 * diff_range, vmax=100 * diff_range)
        else:
            ax.imshow(img)
        ax.set_title(label, fontsize=9)
    for ax in axes.flat:
        ax.set_xticks([])
        ax.set_yticks([])
        if not ax.images:
            ax.axis("off")
    if shown is not None:
        fig.colorbar(shown, ax=axes, orientation="horizontal", shrink=0.5, aspect=40,
                     label=f"{diff_label}, mean of R, G, B [% of the reference's mean]; red: brighter than Mitsuba")
    fig.suptitle(title)
    fig.savefig(path, dpi=100)
    plt.close(fig)


def shown_block_size(noise):
    """The block side k [px] the sheet shows each difference from Mitsuba at (as k×k pixel
    means), for a reference noise `noise` per 2×2 block (a fraction of its mean)."""
    # The sheet shows each difference from Mitsuba as k×k pixel means, k the smallest of 1, 2, 4
    # and 8 that brings the reference's noise there to 8 % of its mean or below, so a noisy
    # reference's speckle does not hide the models' errors (the numbers use 2×2 blocks).
    return next((k for k in (1, 2, 4) if noise * 2 / k <= 0.08), 8)


def model_panels(out, comparison, images, rows, shown_k):
    """Writes each model's image to OUT/LABEL.png; returns the sheet's panels of them (each
    image and its difference from Mitsuba, shown as `shown_k`×`shown_k` pixel means)."""
    ref, mean = comparison.ref, comparison.mean
    shown_as = "" if shown_k == 1 else f"\n({shown_k}×{shown_k} px means)"
    panels = []
    for row in rows:
        label = row["model"]
        ours = images[label]
        shown = tonemap(ours, 1.0 / mean / 4)
        write_png(os.path.join(out, f"{label}.png"), shown)
        panels += [(f"{label}:\n{100 * row['rmse_noise_corrected']:.1f} ± "
                    f"{100 * row['rmse_noise_corrected_se']:.1f} %", shown, "rgb"),
                   (f"{label} − Mitsuba{shown_as}", block_means((ours - ref).mean(2) / mean, shown_k), "diff")]
    return panels


def write_sheet(out, setup, comparison, calibration, refs, lambertian, panels, shown_k):
    """Writes Mitsuba's images (mitsuba.png, mitsuba_lambert.png), the excluded pixels
    (silhouettes.png) and the labelled sheet (sheet.png) of one comparison to `out`: the
    reference, the silhouettes, the calibration, the reference without light between surfaces
    where the scene has several SSS shapes, then the models' `panels`."""
    ref, mean, noise = comparison.ref, comparison.mean, comparison.noise
    cal_a, cal_b, cal_mean, alone = refs.cal_a, refs.cal_b, calibration.mean, refs.alone
    shown_as = "" if shown_k == 1 else f"\n({shown_k}×{shown_k} px means)"
    write_png(os.path.join(out, "mitsuba.png"), tonemap(ref, 1.0 / mean / 4))
    write_png(os.path.join(out, "mitsuba_lambert.png"), tonemap(refs.gi, 1.0 / mean / 4))
    excluded = np.repeat((255 * (1 - refs.edge))[:, :, None], 3, 2).astype(np.uint8)
    write_png(os.path.join(out, "silhouettes.png"), excluded)
    head = [("Mitsuba (path-traced reference)", tonemap(ref, 1.0 / mean / 4), "rgb"),
            ("silhouettes and creases (black: excluded)", excluded, "rgb"),
            ("calibration: --no-sss, Lambertian surfaces", tonemap(lambertian, 1.0 / cal_mean / 4), "rgb"),
            ("calibration − Mitsuba's direct light", (lambertian - 0.5 * (cal_a + cal_b)).mean(2) / cal_mean, "diff")]
    if refs.several:
        m0 = 0.5 * (alone[0] + alone[1])
        head += [("Mitsuba, SSS shapes alone", tonemap(m0, 1.0 / mean / 4), "rgb"),
                 (f"between surfaces: full − alone{shown_as}", block_means((ref - m0).mean(2) / mean, shown_k),
                  "diff")]
    sheet(os.path.join(out, "sheet.png"),
          f"{setup.name} / {setup.material}, {setup.width}×{setup.height}, Mitsuba {setup.spp} spp "
          f"(noise {100 * noise:.1f} % per 2×2 block)\n"
          f"each model's noise-corrected RMSE ± SE (% of the reference's mean)",
          head + panels, 0.2)
