"""A material rendered from Python, as a researcher would compare shading models in a notebook:
Skin1 on the built-in sphere with the default method (pre-integration with the incidence, exit
and entry-shift tables and light through thin parts) and with the plain kernel, side by side with
their difference, as a labelled figure.

    pip install ./crates/python matplotlib
    python examples/python/render.py --out out/python
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import sss

ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
ap.add_argument("--out", default="out/python", help="output folder")
ap.add_argument("--material", default="skin1", help="built-in name or material .toml")
ap.add_argument("--width", type=int, default=480, help="image width [px]")
ap.add_argument("--height", type=int, default=270, help="image height [px]")
ap.add_argument("--photons", type=float, default=1e6, help="profile photon packets per channel")
a = ap.parse_args()
out = Path(a.out)
out.mkdir(parents=True, exist_ok=True)

common = dict(width=a.width, height=a.height, photons=int(a.photons))
best = sss.render(a.material, **common)
plain = sss.render(a.material, incidence_aware=False, exit_aware="off", entry_shift=False, **common)
np.save(out / "render_default.npy", best)


def display(linear):
    """Linear radiance × π to sRGB-ish display values (Reinhard, then γ 2.2)."""
    x = linear / (1.0 + linear)
    return np.clip(x, 0.0, 1.0) ** (1 / 2.2)


fig, axes = plt.subplots(1, 3, figsize=(15, 3.6), constrained_layout=True)
axes[0].imshow(display(best))
axes[0].set_title("default: pre-integration + ρ(θ), h(θ_o; θ_i), δ(θ), translucency")
axes[1].imshow(display(plain))
axes[1].set_title("plain pre-integrated kernel")
diff = (best - plain).mean(axis=2)
lim = float(np.abs(diff).max()) or 1.0
im = axes[2].imshow(diff, cmap="RdBu_r", vmin=-lim, vmax=lim)
axes[2].set_title("default − plain (mean of R, G, B)")
fig.colorbar(im, ax=axes[2], label="difference of π·L (linear, the PFM's units)")
for ax in axes:
    ax.set_xlabel("x [px]")
    ax.set_ylabel("y [px]")
fig.suptitle(f"{a.material} on the built-in sphere, {a.width}×{a.height}, sss.render")
fig.savefig(out / "render_comparison.png", dpi=110)
print(f"wrote {out / 'render_comparison.png'} and {out / 'render_default.npy'}")
