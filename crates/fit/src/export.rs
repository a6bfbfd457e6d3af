//! Kernel files as shader source (HLSL, GLSL, WGSL) or JSON, in the layout of Jimenez et al.'s
//! Separable SSS demo (SSSS), so that engines shipping it can take the numbers as they are.
//!
//! Layout: per separable pass i an array `KERNEL_i` of `KERNEL_TAPS` float4
//! (r weight, g weight, b weight, offset): the centre tap first, then the other taps by increasing
//! offset, exactly as the demo orders its `kernel[]`; and a float3 `KERNEL_SIGN_i`. A rank-N kernel
//! is N horizontal-then-vertical pass pairs whose results are summed with their signs, applied once
//! at that sum (a sign inside each 1D pass would cancel). Offsets and `KERNEL_RANGE` are in the
//! export unit ([`OffsetUnit`]; kernel files hold cm); weights are unitless, integrated over each
//! tap's cell (see [`crate::taps`]). Numbers are the shortest f32 literals that round-trip, always
//! with a decimal point or an exponent so that every language reads them as floats.
//!
//! Scale (thesis eq. 4.11 with the NDC-to-pixel factor H/2): an offset o on a surface at view depth
//! z, both in the same unit, covers o·H / (2·tan(fovy/2)·z) pixels of an image H pixels high. The
//! SSSS shader steps sssWidth·scale·dir/3 with scale = 1/(tan(fovy/2)·z) in texture coordinates,
//! which span the full height (twice NDC's half-height unit), so sssWidth = 1.5 × (scene units per
//! export unit) gives the physical size.

use std::fmt;
use std::str::FromStr;

use serde::Serialize;

use crate::taps::{Pass, ShaderKernel};

/// What [`export`] writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShaderFormat {
    /// HLSL, the demo's own language.
    Hlsl,
    /// GLSL.
    Glsl,
    /// WGSL.
    Wgsl,
    /// JSON: the same numbers as data.
    Json,
}

impl ShaderFormat {
    /// Every format.
    pub const ALL: [ShaderFormat; 4] = [
        ShaderFormat::Hlsl,
        ShaderFormat::Glsl,
        ShaderFormat::Wgsl,
        ShaderFormat::Json,
    ];

    fn name(self) -> &'static str {
        match self {
            ShaderFormat::Hlsl => "hlsl",
            ShaderFormat::Glsl => "glsl",
            ShaderFormat::Wgsl => "wgsl",
            ShaderFormat::Json => "json",
        }
    }
}

impl fmt::Display for ShaderFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ShaderFormat {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|f| f.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| format!("{s:?} is not a format: hlsl, glsl, wgsl or json"))
    }
}

/// Length unit of the exported offsets and range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OffsetUnit {
    /// Centimetres (the unit of kernel files).
    Cm,
    /// Millimetres.
    Mm,
}

impl OffsetUnit {
    /// Every unit.
    pub const ALL: [OffsetUnit; 2] = [OffsetUnit::Cm, OffsetUnit::Mm];

    /// Units per cm: multiplies a length in cm into this unit.
    pub fn per_cm(self) -> f64 {
        match self {
            OffsetUnit::Cm => 1.0,
            OffsetUnit::Mm => 10.0,
        }
    }

    fn name(self) -> &'static str {
        match self {
            OffsetUnit::Cm => "cm",
            OffsetUnit::Mm => "mm",
        }
    }
}

impl fmt::Display for OffsetUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for OffsetUnit {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|u| u.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| format!("{s:?} is not a unit: cm or mm"))
    }
}

/// The kernel `k` (as [`ShaderKernel::from_toml`] returns it) as source text in `format`, offsets
/// and range in `unit`.
pub fn export(k: &ShaderKernel, format: ShaderFormat, unit: OffsetUnit) -> String {
    // Validated kernels are in cm (`from_toml` converts mm); the kernel's own unit is honoured
    // anyway so that a hand-built kernel in mm exports correctly.
    let from: OffsetUnit = k.unit.parse().unwrap_or(OffsetUnit::Cm);
    let scale = unit.per_cm() / from.per_cm();
    let passes: Vec<Vec<[f64; 4]>> = k.pass.iter().map(|p| ssss_order(p, scale)).collect();
    match format {
        ShaderFormat::Json => json(k, unit, scale, &passes),
        _ => shader(k, format, unit, scale, &passes),
    }
}

/// One pass as SSSS's float4 rows (r, g, b, offset·scale): the centre tap first, then the others
/// in their stored (increasing offset) order. The centre is the tap at offset 0 up to rounding of
/// the quadratic mapping (o²/R of an offset within an ulp of 0).
fn ssss_order(p: &Pass, scale: f64) -> Vec<[f64; 4]> {
    let range = p.tap.iter().map(|t| t.offset.abs()).fold(0.0, f64::max);
    let centre = p
        .tap
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.offset.abs().total_cmp(&b.1.offset.abs()))
        .filter(|(_, t)| t.offset.abs() <= 1e-9 * range)
        .map(|(i, _)| i);
    let row = |i: usize| {
        let t = &p.tap[i];
        [t.weight[0], t.weight[1], t.weight[2], t.offset * scale]
    };
    centre
        .into_iter()
        .chain((0..p.tap.len()).filter(|&i| Some(i) != centre))
        .map(row)
        .collect()
}

/// Shortest round-trip f32 literal: always with a decimal point or an exponent (`1.0`, `3.5e-5`).
fn lit(x: f64) -> String {
    format!("{:?}", x as f32)
}

/// Model and material names for a `//` comment: printable ASCII only (GLSL's character set), so
/// that no name can end the comment or continue it onto the next line.
fn comment_safe(s: &str) -> String {
    s.chars()
        .map(|c| {
            if (c.is_ascii_graphic() && c != '\\') || c == ' ' {
                c
            } else {
                '?'
            }
        })
        .collect()
}

fn header(k: &ShaderKernel, unit: OffsetUnit) -> String {
    let (model, material) = (
        comment_safe(&k.model.to_string()),
        comment_safe(&k.material),
    );
    let (taps, passes) = (k.taps, k.pass.len());
    format!(
        "\
// Subsurface-scattering kernel exported by `sss export`.
// Model {model}, material {material}: {taps} taps x {passes} pass(es); offsets and KERNEL_RANGE
// in {unit}; KERNEL_JITTER is the fraction of taps to jitter per pixel (0 = none).
// Layout (SSSS): KERNEL_i[t] = (r weight, g weight, b weight, offset [{unit}]), the centre tap
// first, then the other taps by increasing offset.
// Rank-N kernels: for each pass i blur horizontally, then vertically, with KERNEL_i and add
// KERNEL_SIGN_i * result over the passes; apply the signs once, there, never per 1D pass.
// Scale (thesis eq. 4.11 with the NDC-to-pixel factor H/2): a tap offset o [{unit}] on the surface
// at view depth z [{unit}] covers o * H / (2 * tan(fovy/2) * z) pixels of an image H pixels high.
// The SSSS shader steps finalStep = sssWidth * scale * dir / 3, scale = 1 / (tan(fovy/2) * z), in
// texture coordinates (which span the full height, twice NDC's half-height unit): set
// sssWidth = 1.5 * (scene units per {unit}) to get the physical size.
"
    )
}

fn blur_comment(unit: OffsetUnit) -> String {
    format!(
        "\
// Reference 1D pass with KERNEL_<pass_index> along dir ((1, 0), then (0, 1)):
//   sum over taps of weight.rgb * colour(uv + dir * offset * pixels_per_unit_at_unit_depth / z * texel)
// z: the pixel's view depth [{unit}]; pixels_per_unit_at_unit_depth = H / (2 * tan(fovy/2)) [pixels
// per {unit} at depth 1 {unit}]; texel = 1 / resolution. No depth test and no jitter: production
// code adds SSSS's follow-surface lerp toward the centre colour where depths differ.
"
    )
}

/// Source in one of the three shading languages; they differ only in spelling.
fn shader(
    k: &ShaderKernel,
    format: ShaderFormat,
    unit: OffsetUnit,
    scale: f64,
    passes: &[Vec<[f64; 4]>],
) -> String {
    let (vec3, vec4) = match format {
        ShaderFormat::Hlsl => ("float3", "float4"),
        ShaderFormat::Glsl => ("vec3", "vec4"),
        _ => ("vec3<f32>", "vec4<f32>"),
    };
    let ctor = |name: &str, xs: &[f64]| {
        let xs: Vec<String> = xs.iter().map(|&x| lit(x)).collect();
        format!("{name}({})", xs.join(", "))
    };
    let (n, range, jitter) = (passes.len(), lit(k.range * scale), lit(k.jitter));
    let mut s = header(k, unit);
    s += &match format {
        ShaderFormat::Hlsl => format!(
            "#define KERNEL_TAPS {}\n#define KERNEL_PASSES {n}\nstatic const float KERNEL_RANGE = {range};\nstatic const float KERNEL_JITTER = {jitter};\n",
            k.taps
        ),
        ShaderFormat::Glsl => format!(
            "#define KERNEL_TAPS {}\n#define KERNEL_PASSES {n}\nconst float KERNEL_RANGE = {range};\nconst float KERNEL_JITTER = {jitter};\n",
            k.taps
        ),
        _ => format!(
            "const KERNEL_TAPS: u32 = {}u;\nconst KERNEL_PASSES: u32 = {n}u;\nconst KERNEL_RANGE: f32 = {range};\nconst KERNEL_JITTER: f32 = {jitter};\n",
            k.taps
        ),
    };
    for (i, (p, rows)) in k.pass.iter().zip(passes).enumerate() {
        let sign = ctor(vec3, &p.sign);
        let rows: Vec<String> = rows
            .iter()
            .map(|r| format!("    {}", ctor(vec4, r)))
            .collect();
        let rows = rows.join(",\n");
        s += &match format {
            ShaderFormat::Hlsl => format!(
                "\nstatic const float3 KERNEL_SIGN_{i} = {sign};\nstatic const float4 KERNEL_{i}[KERNEL_TAPS] = {{\n{rows}\n}};\n"
            ),
            ShaderFormat::Glsl => format!(
                "\nconst vec3 KERNEL_SIGN_{i} = {sign};\nconst vec4 KERNEL_{i}[KERNEL_TAPS] = vec4[KERNEL_TAPS](\n{rows}\n);\n"
            ),
            _ => format!(
                "\nconst KERNEL_SIGN_{i}: vec3<f32> = {sign};\nconst KERNEL_{i} = array<vec4<f32>, KERNEL_TAPS>(\n{rows}\n);\n"
            ),
        };
    }
    // Tap i of pass `pass_index`: one branch per pass after the first.
    let branches: String = (1..n)
        .map(|i| match format {
            ShaderFormat::Wgsl => {
                format!("    if pass_index == {i}u {{ return KERNEL_{i}[i]; }}\n")
            }
            _ => format!("    if (pass_index == {i}) return KERNEL_{i}[i];\n"),
        })
        .collect();
    s += "\n";
    s += &blur_comment(unit);
    s += &match format {
        ShaderFormat::Hlsl => format!(
            "\
float4 kernel_tap(int pass_index, int i) {{
{branches}    return KERNEL_0[i];
}}

float3 sss_blur(int pass_index, Texture2D color, SamplerState color_sampler, float2 uv, float2 dir,
                float z, float pixels_per_unit_at_unit_depth, float2 texel) {{
    float2 step_uv = dir * (pixels_per_unit_at_unit_depth / z) * texel;
    float3 sum = float3(0.0, 0.0, 0.0);
    for (int i = 0; i < KERNEL_TAPS; i++) {{
        float4 k = kernel_tap(pass_index, i);
        sum += k.rgb * color.SampleLevel(color_sampler, uv + k.a * step_uv, 0.0).rgb;
    }}
    return sum;
}}
"
        ),
        ShaderFormat::Glsl => format!(
            "\
vec4 kernel_tap(int pass_index, int i) {{
{branches}    return KERNEL_0[i];
}}

vec3 sss_blur(int pass_index, sampler2D color, vec2 uv, vec2 dir, float z,
              float pixels_per_unit_at_unit_depth, vec2 texel) {{
    vec2 step_uv = dir * (pixels_per_unit_at_unit_depth / z) * texel;
    vec3 sum = vec3(0.0);
    for (int i = 0; i < KERNEL_TAPS; i++) {{
        vec4 k = kernel_tap(pass_index, i);
        sum += k.rgb * textureLod(color, uv + k.a * step_uv, 0.0).rgb;
    }}
    return sum;
}}
"
        ),
        _ => format!(
            "\
fn kernel_tap(pass_index: u32, i: u32) -> vec4<f32> {{
{branches}    return KERNEL_0[i];
}}

fn sss_blur(pass_index: u32, color: texture_2d<f32>, color_sampler: sampler, uv: vec2<f32>,
            dir: vec2<f32>, z: f32, pixels_per_unit_at_unit_depth: f32, texel: vec2<f32>) -> vec3<f32> {{
    let step_uv = dir * (pixels_per_unit_at_unit_depth / z) * texel;
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < KERNEL_TAPS; i++) {{
        let k = kernel_tap(pass_index, i);
        sum += k.rgb * textureSampleLevel(color, color_sampler, uv + k.a * step_uv, 0.0).rgb;
    }}
    return sum;
}}
"
        ),
    };
    s
}

#[derive(Serialize)]
struct JsonKernel {
    model: String,
    material: String,
    unit: String,
    taps: usize,
    range: f32,
    jitter: f32,
    layout: &'static str,
    passes: Vec<JsonPass>,
}

/// f32 fields: serde_json writes them as the shortest f32 that round-trips.
#[derive(Serialize)]
struct JsonPass {
    sign: [f32; 3],
    kernel: Vec<[f32; 4]>,
}

fn json(k: &ShaderKernel, unit: OffsetUnit, scale: f64, passes: &[Vec<[f64; 4]>]) -> String {
    let j = JsonKernel {
        model: k.model.to_string(),
        material: k.material.clone(),
        unit: unit.to_string(),
        taps: k.taps,
        range: (k.range * scale) as f32,
        jitter: k.jitter as f32,
        layout: "ssss: [r, g, b, offset], centre tap first",
        passes: k
            .pass
            .iter()
            .zip(passes)
            .map(|(p, rows)| JsonPass {
                sign: p.sign.map(|s| s as f32),
                kernel: rows.iter().map(|r| r.map(|x| x as f32)).collect(),
            })
            .collect(),
    };
    serde_json::to_string_pretty(&j).expect("kernel serializes") + "\n"
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::skin::Skin;
    use crate::taps::TapSpec;
    use crate::{KernelModel, Profile, SkinParams};

    fn profile() -> Profile {
        Profile::from_fn(0.01, 60, |_, r| (-r / 0.1).exp() / r.max(0.005))
    }

    /// A kernel as a file would hold it: built, written as TOML and read back.
    fn via_toml(model: KernelModel) -> ShaderKernel {
        let f = model.fit(&profile(), "skin1").unwrap();
        let k = ShaderKernel::from_fitted(&f, "skin1", TapSpec::default()).unwrap();
        ShaderKernel::from_toml(&k.to_toml(), "k.toml").unwrap()
    }

    fn svd3() -> ShaderKernel {
        via_toml(KernelModel::Svd {
            rank: 3,
            renormalize: false,
        })
    }

    fn skin() -> ShaderKernel {
        via_toml(KernelModel::Skin(SkinParams::Given(Skin::DEMO)))
    }

    /// Numbers inside the first `name(` … `)` of `line`.
    fn args(line: &str, name: &str) -> Vec<f64> {
        let start = line.find(&format!("{name}(")).unwrap() + name.len() + 1;
        let end = start + line[start..].find(')').unwrap();
        line[start..end]
            .split(',')
            .map(|x| x.trim().parse().unwrap())
            .collect()
    }

    /// (signs, rows) per pass scanned from shader text: `KERNEL_SIGN_i` lines and array rows
    /// (lines starting with the float4 constructor), grouped by `taps`.
    fn scan(text: &str, vec3: &str, vec4: &str, taps: usize) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
        let signs = text
            .lines()
            .filter(|l| !l.starts_with("//") && l.contains("KERNEL_SIGN_") && l.contains('='))
            .map(|l| args(l, vec3))
            .collect();
        let rows: Vec<f64> = text
            .lines()
            .filter(|l| l.trim_start().starts_with(&format!("{vec4}(")))
            .flat_map(|l| args(l, vec4))
            .collect();
        (signs, rows.chunks(4 * taps).map(|c| c.to_vec()).collect())
    }

    fn scan_json(text: &str) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
        let v: serde_json::Value = serde_json::from_str(text).unwrap();
        let nums = |x: &serde_json::Value| -> Vec<f64> {
            x.as_array()
                .unwrap()
                .iter()
                .flat_map(|y| match y.as_array() {
                    Some(a) => a.iter().map(|z| z.as_f64().unwrap()).collect(),
                    None => vec![y.as_f64().unwrap()],
                })
                .collect()
        };
        let passes = v["passes"].as_array().unwrap();
        (
            passes.iter().map(|p| nums(&p["sign"])).collect(),
            passes.iter().map(|p| nums(&p["kernel"])).collect(),
        )
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-6 * b.abs() + f32::MIN_POSITIVE as f64
    }

    #[test]
    fn names_round_trip() {
        for f in ShaderFormat::ALL {
            assert_eq!(f.to_string().parse::<ShaderFormat>(), Ok(f));
        }
        for u in OffsetUnit::ALL {
            assert_eq!(u.to_string().parse::<OffsetUnit>(), Ok(u));
        }
        assert!("spirv".parse::<ShaderFormat>().is_err());
        assert!("in".parse::<OffsetUnit>().is_err());
    }

    #[test]
    fn wgsl_and_glsl_validate_with_naga() {
        use naga::valid::{Capabilities, ValidationFlags, Validator};
        for k in [svd3(), skin()] {
            let n = k.pass.len();
            let wgsl = export(&k, ShaderFormat::Wgsl, OffsetUnit::Mm);
            let module = naga::front::wgsl::parse_str(&wgsl)
                .unwrap_or_else(|e| panic!("{}\n{wgsl}", e.emit_to_string(&wgsl)));
            Validator::new(ValidationFlags::all(), Capabilities::all())
                .validate(&module)
                .unwrap_or_else(|e| panic!("{e:?}\n{wgsl}"));

            // naga's GLSL front end reads Vulkan GLSL, which has no combined `sampler2D` type:
            // the test passes a texture2D and a sampler instead and combines them at the call.
            let glsl = export(&k, ShaderFormat::Glsl, OffsetUnit::Mm)
                .replace(
                    "sampler2D color,",
                    "texture2D color_texture, sampler color_sampler,",
                )
                .replace(
                    "textureLod(color,",
                    "textureLod(sampler2D(color_texture, color_sampler),",
                );
            let calls: String = (0..n)
                .map(|i| format!("    sum += KERNEL_SIGN_{i} * sss_blur({i}, color_texture, color_sampler, v_uv, vec2(1.0, 0.0), 2.0, 1000.0, vec2(1.0 / 512.0));\n"))
                .collect();
            let src = format!(
                "#version 450\n{glsl}\nlayout(set = 0, binding = 0) uniform texture2D color_texture;\nlayout(set = 0, binding = 1) uniform sampler color_sampler;\nlayout(location = 0) in vec2 v_uv;\nlayout(location = 0) out vec4 o_color;\n\nvoid main() {{\n    vec3 sum = vec3(0.0);\n{calls}    o_color = vec4(sum, 1.0);\n}}\n"
            );
            let module = naga::front::glsl::Frontend::default()
                .parse(
                    &naga::front::glsl::Options::from(naga::ShaderStage::Fragment),
                    &src,
                )
                .unwrap_or_else(|e| panic!("{}\n{src}", e.emit_to_string(&src)));
            Validator::new(ValidationFlags::all(), Capabilities::all())
                .validate(&module)
                .unwrap_or_else(|e| panic!("{e:?}\n{src}"));
        }
    }

    #[test]
    fn numbers_round_trip_in_every_format_and_unit() {
        for k in [svd3(), skin()] {
            for unit in OffsetUnit::ALL {
                // Expected layout, built independently: the zero-offset tap moved to the front.
                let want: Vec<Vec<f64>> = k
                    .pass
                    .iter()
                    .map(|p| {
                        let mut t: Vec<_> = p.tap.iter().collect();
                        t.sort_by_key(|t| t.offset != 0.0);
                        t.iter()
                            .flat_map(|t| {
                                [
                                    t.weight[0],
                                    t.weight[1],
                                    t.weight[2],
                                    t.offset * unit.per_cm(),
                                ]
                            })
                            .collect()
                    })
                    .collect();
                for format in ShaderFormat::ALL {
                    let text = export(&k, format, unit);
                    let (signs, rows) = match format {
                        ShaderFormat::Hlsl => scan(&text, "float3", "float4", k.taps),
                        ShaderFormat::Glsl => scan(&text, "vec3", "vec4", k.taps),
                        ShaderFormat::Wgsl => scan(&text, "vec3<f32>", "vec4<f32>", k.taps),
                        ShaderFormat::Json => scan_json(&text),
                    };
                    assert_eq!(rows.len(), k.pass.len(), "{format} {unit}");
                    for (p, (s, (got, want))) in
                        k.pass.iter().zip(signs.iter().zip(rows.iter().zip(&want)))
                    {
                        assert_eq!(s, &p.sign.to_vec(), "{format} {unit}");
                        assert_eq!(got.len(), want.len(), "{format} {unit}");
                        for (g, w) in got.iter().zip(want) {
                            assert!(close(*g, *w), "{format} {unit}: {g} vs {w}");
                        }
                    }
                    if format != ShaderFormat::Json {
                        assert!(text.contains(&format!("offset [{unit}]")), "{format}");
                    }
                }
            }
        }
    }

    /// The SSSS demo's skin kernel (17 taps, width 1) in mm, as its shader lists it.
    #[test]
    fn skin_demo_matches_the_ssss_table() {
        let f = KernelModel::Skin(SkinParams::Given(Skin::DEMO))
            .fit(&profile(), "skin1")
            .unwrap();
        let k = ShaderKernel::from_fitted(&f, "skin1", TapSpec::default()).unwrap();
        let (_, rows) = scan_json(&export(&k, ShaderFormat::Json, OffsetUnit::Mm));
        let golden = [
            [0.536343, 0.624624, 0.748867, 0.0],
            [0.00317394, 0.000134823, 3.77269e-05, -2.0],
            [0.0100386, 0.000914679, 0.000275702, -1.53125],
            [0.0144609, 0.00317269, 0.00106399, -1.125],
        ];
        for (got, want) in rows[0].chunks(4).zip(golden) {
            for c in 0..3 {
                assert!(
                    (got[c] - want[c]).abs() <= 1e-5 * want[c],
                    "{got:?} vs {want:?}"
                );
            }
            assert_eq!(got[3], want[3]);
        }
    }
}
