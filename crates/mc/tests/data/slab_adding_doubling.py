"""Adding-doubling reference for `crates/mc/tests/body.rs`: total reflectance and transmittance of
a slab under a normally incident collimated beam, by iadpython (Prahl's adding-doubling, the
Python port of `iad`), `pip install iadpython scipy`. Run with `python3 slab_adding_doubling.py`.

The slabs: in air, refractive index n, absorption mu_a and scattering mu_s [1/cm], Henyey-
Greenstein g, thickness d [cm]. iadpython takes the albedo a = mu_s/(mu_a + mu_s) and the optical
thickness b = (mu_a + mu_s) d. UR1 is the total reflectance for collimated normal incidence,
specular reflection included; UT1 the total transmittance, unscattered light included.

Quadrature: with index-mismatched boundaries the result converges slowly in the number of
quadrature points (the thick slab's UR1: 0.21063 at 16, 0.21048 at 32, 0.21047 at 40), so those
slabs use 40; the index-matched slab uses 24 (iadpython 0.5.3 loses accuracy there from 32 points
on: UT1 0.66050 at 32, 0.3217 at 40). The printed `spread` is the change of UR1 or UT1 from 8
points fewer: the reference's own uncertainty, far below the Monte Carlo's standard errors in the
tests.
"""

import iadpython

SLABS = [
    # (n, mu_a, mu_s, g, d)
    (1.0, 10.0, 90.0, 0.75, 0.02),  # van de Hulst's slab (MCML's validation): 0.09739, 0.66096
    (1.4, 1.0, 30.0, 0.8, 0.005),  # thin: optical thickness 0.155
    (1.4, 1.0, 30.0, 0.8, 0.05),
    (1.4, 1.0, 30.0, 0.8, 0.2),
    (1.4, 1.0, 30.0, 0.8, 1.0),
    (1.4, 1.0, 30.0, 0.8, 3.0),  # thick: 14 diffusion lengths, the half-space limit
]


def rt(n, mu_a, mu_s, g, d, quad_pts):
    mu_t = mu_a + mu_s
    s = iadpython.Sample(a=mu_s / mu_t, b=mu_t * d, g=g, d=d, n=n, quad_pts=quad_pts)
    ur1, ut1, _, _ = s.rt()
    return float(ur1), float(ut1)


print(f"iadpython {iadpython.__version__}")
print("n, mu_a, mu_s, g, d, UR1, UT1, spread")
for slab in SLABS:
    quad_pts = 24 if slab[0] == 1.0 else 40
    ur1, ut1 = rt(*slab, quad_pts)
    ur1_coarse, ut1_coarse = rt(*slab, quad_pts - 8)
    spread = max(abs(ur1 - ur1_coarse), abs(ut1 - ut1_coarse))
    print(", ".join(str(x) for x in slab) + f", {ur1:.6f}, {ut1:.6f}, {spread:.1e}")
