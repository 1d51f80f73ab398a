//! Code shlight writes: a light's WGSL, GLSL, HLSL or C snippet
//! (`--format wgsl|glsl|hlsl|c`, any encoding) and a volume's WGSL or GLSL
//! lookup (`convert VOLUME -o NAME.wgsl|glsl`). Each starts with a comment
//! saying what it computes; the table repeats it.

use super::Header;

/// A snippet: its first line is a `//` comment naming shlight; `None` for
/// other text.
pub(super) fn describe(text: &str) -> Option<Header> {
    let first = text.lines().next()?.strip_prefix("// shlight")?;
    let language = if text.contains("#include <math.h>") {
        "C"
    } else if text.contains("static const ") {
        "HLSL"
    } else if text.contains("var<private>") || text.contains("\nfn ") {
        "WGSL"
    } else {
        "GLSL"
    };
    let volume = text.contains("shlight_volume_irradiance");
    let mut h = Header::new(format!(
        "{language} code: {}",
        if volume {
            "an irradiance volume's lookup (shlight convert VOLUME -o NAME.wgsl|glsl), \
             which reads the volume's KTX2 textures"
        } else {
            "a light's coefficients and its evaluator (shlight convert/project --format)"
        }
    ));
    h.field("what", format!("shlight{first}"));
    let constant = |name: &str| {
        text.lines()
            .filter(|l| !l.trim_start().starts_with("//"))
            .find_map(|l| {
                let at = l.find(name)?;
                let rest = &l[at + name.len()..];
                // `NAME: i32 = 4;`, `NAME = 4;` or `#define NAME 4`.
                let digits: String = rest
                    .trim_start_matches([':', ' ', '='])
                    .trim_start_matches("i32")
                    .trim_start_matches([' ', '='])
                    .chars()
                    .take_while(char::is_ascii_digit)
                    .collect();
                (!digits.is_empty()).then_some(digits)
            })
    };
    if let Some(lmax) = constant("SHLIGHT_VOLUME_LMAX").or_else(|| constant("SHLIGHT_LMAX")) {
        h.field("lmax", lmax);
    }
    for line in text.lines() {
        if let Some(texture) = line
            .strip_prefix("// - ")
            .and_then(|l| l.split_once(".ktx2: "))
        {
            h.field("texture", format!("{}.ktx2: {}", texture.0, texture.1));
        }
    }
    h.rows = "# its header comment:\n".to_string();
    for line in text.lines().take_while(|l| l.starts_with("//")) {
        h.rows.push_str(line);
        h.rows.push('\n');
    }
    Some(h)
}
