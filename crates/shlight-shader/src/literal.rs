//! Float literals every target language reads.

/// A float literal every target language reads (C, GLSL, HLSL, WGSL):
/// the shortest decimal that reads back as `v` in f64, always with a `.`
/// or an exponent (`1.0`, `0.28209479177387814`, `1e39`).
#[must_use]
pub fn float_literal(v: f64) -> String {
    let s = format!("{v:?}");
    if s.contains(['.', 'e', 'E']) {
        s
    } else {
        format!("{s}.0")
    }
}

/// A literal of `x` rounded to f32: the shortest decimal that reads back
/// as that f32 (`0.2820948`, `3.0`, `1e-9`).
#[must_use]
pub fn f32_literal(x: f64) -> String {
    format!("{:?}", x as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn literals_round_trip_to_the_f32_value() {
        for x in [0.282_094_791_773_878_14, -1.224_744_871_391_589, 3.0, 1e-9] {
            let text = f32_literal(x);
            assert!(text.contains('.') || text.contains('e'), "{text}");
            assert_eq!(text.parse::<f32>().unwrap(), x as f32);
        }
    }
}
