"""Two materials from measured coefficients to shader kernels, as a researcher would do it in a
notebook: simulate their Rd(r), plot r·Rd(r) with its standard error, fit and plot 17-tap
pre-integrated kernels, and write one as HLSL.

    pip install ./crates/python matplotlib
    python examples/python/kernels.py --out out/python
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
ap.add_argument("--photons", type=float, default=1e6, help="photon packets per channel")
a = ap.parse_args()
out = Path(a.out)
out.mkdir(parents=True, exist_ok=True)

fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
colours = {"R": "tab:red", "G": "tab:green", "B": "tab:blue"}
for name, style in (("skin1", "-"), ("marble", "--")):
    p = sss.simulate(name, photons=int(a.photons), seed=1)
    r = p["r_cm"][:-1]  # the last bin is MCML's overflow bin
    for c, ch in enumerate("RGB"):
        y, se = r * p["rd"][:-1, c], r * p["rd_se"][:-1, c]
        left.plot(r, y, style, color=colours[ch], label=f"{name} {ch}")
        left.fill_between(r, y - 2 * se, y + 2 * se, color=colours[ch], alpha=0.25, lw=0)
    k = sss.fit(p, model="preint", material=name)
    for c, ch in enumerate("RGB"):
        right.plot(k.offsets[0], k.weights[0, :, c], style + "o", ms=3, color=colours[ch],
                   label=f"{name} {ch}")
    if name == "skin1":
        (out / "skin1.hlsl").write_text(sss.export(k, format="hlsl"))
left.set(xlim=(0, 1.0), xlabel="r [cm]", ylabel="r·Rd(r) [cm⁻¹]",
         title=f"Monte Carlo profiles ({a.photons:.0e} photons, ±2 SE bands)")
right.set(xlabel="tap offset [cm]", ylabel="tap weight [-]",
          title="17-tap pre-integrated kernels (one 1D pass)")
for ax in (left, right):
    ax.legend(fontsize=7, ncol=2)
    ax.grid(alpha=0.3)
fig.tight_layout()
fig.savefig(out / "profiles_and_kernels.png", dpi=120)
print(f"wrote {out / 'profiles_and_kernels.png'} and {out / 'skin1.hlsl'}")
