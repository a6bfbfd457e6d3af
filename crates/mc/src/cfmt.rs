//! C `printf` number formats (`%G`, `%E`) so `.mco` files match MCML's byte for byte.

/// `%.{prec}E`: mantissa with `prec` decimals, exponent with sign and at least two digits.
pub fn c_e(x: f64, prec: usize) -> String {
    if !x.is_finite() {
        return c_nonfinite(x);
    }
    let s = format!("{x:.prec$e}");
    let (mant, exp) = s
        .split_once('e')
        .expect("Rust's {:e} always has an exponent");
    let exp: i32 = exp.parse().expect("integer exponent");
    format!("{mant}E{}{:02}", if exp < 0 { '-' } else { '+' }, exp.abs())
}

/// `%.{prec}G`: the shorter of fixed and exponential with `prec` significant digits, trailing
/// zeros removed.
pub fn c_g(x: f64, prec: usize) -> String {
    if !x.is_finite() {
        return c_nonfinite(x);
    }
    if x == 0.0 {
        return if x.is_sign_negative() {
            "-0".into()
        } else {
            "0".into()
        };
    }
    let p = prec.max(1);
    let s = format!("{x:.prec$e}", prec = p - 1);
    let (mant, exp) = s.split_once('e').expect("exponent");
    let exp: i32 = exp.parse().expect("integer exponent");
    if exp < -4 || exp >= p as i32 {
        let mant = strip_zeros(mant);
        format!("{mant}E{}{:02}", if exp < 0 { '-' } else { '+' }, exp.abs())
    } else {
        let decimals = (p as i32 - 1 - exp) as usize;
        strip_zeros(&format!("{x:.decimals$}")).to_string()
    }
}

fn strip_zeros(s: &str) -> &str {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s
    }
}

fn c_nonfinite(x: f64) -> String {
    if x.is_nan() {
        "NAN".into()
    } else if x > 0.0 {
        "INF".into()
    } else {
        "-INF".into()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_glibc_printf() {
        // Expected strings as glibc prints them.
        assert_eq!(c_g(0.0243187, 6), "0.0243187");
        assert_eq!(c_g(1e8, 6), "1E+08");
        assert_eq!(c_g(100000.0, 6), "100000");
        assert_eq!(c_g(1234567.0, 6), "1.23457E+06");
        assert_eq!(c_g(0.0001, 6), "0.0001");
        assert_eq!(c_g(0.00001234, 6), "1.234E-05");
        assert_eq!(c_g(1.37, 6), "1.37");
        assert_eq!(c_g(0.9, 4), "0.9");
        assert_eq!(c_e(0.0, 4), "0.0000E+00");
        assert_eq!(c_e(123.456, 4), "1.2346E+02");
        assert_eq!(c_e(1.5e-7, 4), "1.5000E-07");
        assert_eq!(c_e(2.0e-120, 4), "2.0000E-120");
    }
}
