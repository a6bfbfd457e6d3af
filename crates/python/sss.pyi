"""Measured optical coefficients to subsurface-scattering kernels: Monte Carlo profiles (an
MCML-style tracer), analytic profiles, separable kernel fits, shader export and engine
parameters. Lengths in cm, coefficients in cm⁻¹, Rd(r) in cm⁻²."""

from typing import Any, Callable, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

Material = Union[str, Mapping[str, Any]]
"""A built-in name (see `materials()`), a path to a material .toml file, or a dict with
`sigma_a` and `sigma_s` [cm⁻¹], `g` [-] (default 0) and `eta` [-], each one value or three
(R, G, B), optionally `name` and `thickness` [cm]; or a layered sample, a dict with `layers`
(such dicts from the top, each with `thickness` [cm] except the last, a half-space if left out)
and optionally `name` (not for `engine_params`, `target_error` or `incidence_angles`)."""

Profile = Mapping[str, Any]
"""The dict `simulate` or `profile` returns: `r_cm` (nr), `rd` and `rd_se` (nr × 3) [cm⁻²] whose
last bin is MCML's overflow bin, `dr_cm`."""

Number = Union[int, float]

class SssError(ValueError):
    """Bad input (the message names the argument and its value) or a failed run."""

class Kernel:
    """A shader-ready separable kernel: per pass its taps' offsets [cm], RGB weights and signs."""

    @property
    def model(self) -> str:
        """The model, as `sss fit --model` names it."""
    @property
    def material(self) -> str: ...
    @property
    def taps(self) -> int:
        """Taps per 1D pass."""
    @property
    def range_cm(self) -> float:
        """Range of the offsets' quadratic mapping [cm]."""
    @property
    def offsets(self) -> npt.NDArray[np.float64]:
        """Tap offsets, passes × taps [cm]."""
    @property
    def weights(self) -> npt.NDArray[np.float64]:
        """Tap weights, passes × taps × 3 (R, G, B) [-]."""
    @property
    def signs(self) -> npt.NDArray[np.float64]:
        """Each pass's sign per channel, passes × 3 (±1)."""
    def to_toml(self) -> str:
        """The kernel file `sss fit` writes, which `sss render --kernel` reads."""
    @staticmethod
    def from_toml(text: str) -> "Kernel": ...

def materials() -> list[dict[str, Any]]:
    """The built-in materials: `name`, `source`, `sigma_a`, `sigma_s` [cm⁻¹], `g`, `eta`."""

def simulate(
    material: Material,
    photons: Optional[Number] = None,
    seed: Optional[int] = None,
    threads: Optional[int] = None,
    full: bool = False,
    incidence_angles: Optional[Sequence[float]] = None,
    incidence_photons: Optional[Number] = None,
    target_error: Optional[float] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
) -> dict[str, Any]:
    """Rd(r) by the MCML-style tracer at the thesis's settings unless told otherwise (photons
    [default 1e7] per channel, seed [default 1]: same seed, same numbers as `sss simulate`, for
    any `threads`). Returns `r_cm`, `rd`, `rd_se` (nr × 3) [cm⁻²] (last bin: MCML's overflow
    bin), totals `rd_total`, `a_total`, `tt_total` with `_se`, `rsp`, the grid (`dr_cm`, `nr`,
    `dz_cm`, `nz`), `photons`, `seed`, `threads`, `seconds`; with `full`, `a_rz` (3 × nr × nz)
    [cm⁻³]; `a_layers` (3 × layers) [-]; with `incidence_angles` [degrees], `incidence`
    (`theta_deg`, `rd`, `rd_se`, `rsp`).
    The GIL is released while tracing; Ctrl-C raises KeyboardInterrupt within about a second
    (not within a `target_error` run)."""

def read_mco(path: str) -> dict[str, Any]:
    """An MCML output file: totals, bin widths and 1D arrays (`rd_r`, `tt_r`, `a_z`, ...)."""

def run_mci(
    path: str, photons: Optional[Number] = None, seed: Optional[int] = None
) -> list[dict[str, Any]]:
    """Every run of an MCML input file, traced as MCML traces it, as dicts of arrays."""

def profile(material: Material, model: str = "pbd") -> dict[str, Any]:
    """An analytic profile ("dipole", "better-dipole", "directional-dipole", "pbd", "burley")
    on the material's thesis grid, as the dict `simulate` returns."""

Source = Union[Profile, Material]
"""A profile (the dict `simulate` or `profile` returns), or a material traced at the thesis's
settings with `photons` per channel [default 1e7] (Ctrl-C stops it)."""

def fit(
    source: Source,
    model: str = "preint",
    taps: Optional[int] = None,
    material: Optional[str] = None,
    photons: Optional[Number] = None,
) -> Kernel:
    """A kernel model fitted to the profile and sampled into `taps` taps per pass [default 17].
    model as `sss fit --model`: "preint", "svd", "svd2", "svd2-renorm", "guided",
    "guided-k1.55-b50", "manual", "deon3", "skin", "skin-fit", "burley"."""

def export(kernel: Kernel, format: str = "hlsl", unit: str = "cm") -> str:
    """Shader source: "hlsl", "glsl", "wgsl" or "json" (SSSS's layout); offsets in "cm" or "mm"."""

def kernel(
    source: Source,
    budget: str = "2x17",
    material: Optional[str] = None,
    photons: Optional[Number] = None,
) -> Tuple[Kernel, list[dict[str, Any]]]:
    """The best kernel within the budget PASSESxTAPS by mean image RMS, and the ranking
    (`model`, `passes`, `image_rms` per channel, `mean_image_rms`)."""

def evaluate(
    source: Source, material: Optional[str] = None, photons: Optional[Number] = None
) -> list[dict[str, Any]]:
    """Every kernel model's errors on the profile: the rows of `sss eval --json`."""

def engine_params(
    material: Material,
    engine: str = "unreal",
    profile: Optional[Profile] = None,
    budget: str = "2x17",
    photons: Optional[Number] = None,
) -> dict[str, Any]:
    """Engine parameters ("unreal", "unity", "blender", "openpbr") as `sss engine-params --json`:
    `params`, `burley_fit`, `best_separable`; the profile is simulated when not given."""

Switch = Union[bool, str, None]
"""True/False or "on"/"off"; None takes the method's default."""

def render(
    material: Union[Material, Sequence[Material], None] = None,
    *,
    scene: str = "sphere",
    width: int = 1920,
    height: int = 1080,
    light: Union[str, Sequence[str], None] = None,
    method: str = "separable",
    kernel: Optional[Kernel] = None,
    taps: int = 17,
    error_target: Optional[float] = None,
    incidence_aware: Switch = None,
    exit_aware: Optional[str] = None,
    entry_shift: Switch = None,
    translucency: Switch = None,
    albedo: str = "pre-post",
    depth_test: str = "lerp",
    tolerance: Optional[float] = None,
    jitter: Optional[float] = None,
    resolution: str = "full",
    blur: str = "exact",
    sss_width: float = 1.0,
    exposure: float = 1.0,
    camera: Union[Sequence[float], str, None] = None,
    target: Union[Sequence[float], str, None] = None,
    fov: Optional[float] = None,
    object_albedo: Union[Sequence[float], Sequence[Sequence[float]], None] = None,
    floor_albedo: Union[Sequence[float], str, None] = None,
    specular: Optional[float] = None,
    ambient: Optional[float] = None,
    no_sss: bool = False,
    photons: Optional[Number] = None,
    seed: Optional[int] = None,
    incidence_photons: Optional[Number] = None,
    translucency_photons: Optional[Number] = None,
    bssrdf: str = "directional",
    samples: int = 16,
    frames: int = 16,
    frame_seed: Optional[int] = None,
    radius: Optional[float] = None,
    dipole_energy: str = "monte-carlo",
    light_map: int = 1024,
    denoise: Union[bool, str, None] = None,
) -> npt.NDArray[np.float32]:
    """A scene drawn with the material's subsurface scattering: linear radiance (height × width ×
    3, float32, top row first), equal to the render.pfm `sss render` writes for the same
    arguments. Defaults as `sss render`'s: Skin1 on the built-in sphere, pre-integration with the
    incidence, exit (at the entry angle) and entry-shift tables and light through thin parts.
    method: "separable", "directional-dipole", "area-gather" or "surface-gather"; light as `sss
    render --light` writes it ("dir:X,Y,Z[:E]", "point:X,Y,Z[:I]", "area:X,Y,Z:AX,AY,AZ:SIDE[:L]");
    exit_aware: "entry", "on" or "off". Needs a GPU adapter (Mesa's lavapipe will do); raises
    SssError naming the argument on bad input."""

def package(
    material: Optional[Material] = None,
    *,
    taps: int = 17,
    photons: Optional[Number] = None,
    seed: Optional[int] = None,
    incidence_photons: Optional[Number] = None,
    translucency_photons: Optional[Number] = None,
) -> dict[str, Any]:
    """A material's whole shading model as `sss export MATERIAL --format package` writes it:
    "files" (file name → bytes: README.md, tables.json, tables.bin, kernel.*, sss_lookups.wgsl,
    .glsl, .hlsl) and the tables as float32 arrays: "angles_deg" (9,), "incidence" and
    "incidence_se" (9 × 3, ρ(θ)/ρ(0)), "exit" and "exit_se" (9 × 9 × 3, h(θ_o; θ_i) as
    [θ_i][θ_o]), "entry_shift_cm" and "entry_shift_se_cm" (9 × 3), "translucency" (a dict:
    "thickness_cm" (16,), "tt_over_rho" (16 × 3), "exit" (16 × 9 × 3), "rho", "rho_se" (3,)),
    "eta" and "notes". Needs no GPU; raises SssError naming the argument on bad input."""
    ...

def light_scale_curvature(
    positions: npt.ArrayLike,
    normals: npt.ArrayLike,
    triangles: npt.ArrayLike,
    mean_cm: npt.ArrayLike,
) -> npt.NDArray[np.float32]:
    """The curvature [cm⁻¹] of a triangle mesh at the scale light travels in a material, per
    vertex and channel (n × 3): each vertex's chord curvatures (n_y − n_x)·(y − x)/|y − x|² to the
    other vertices of its body facing its way, weighted e^{−r/s}/r per unit area, s = `mean_cm`
    per channel (the half-space's mean exit distance, the shape table's ⟨s⟩ at κ = 0 and θ = 0).
    1/R on a sphere at any scale, 0 on a plane: what `sss_shape_energy` reads per channel.
    `positions` and `normals` (n × 3, cm and unit outward), `triangles` (m × 3 indices). Raises
    SssError naming the argument on bad input."""
    ...
