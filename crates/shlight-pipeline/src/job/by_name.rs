//! [`by_name`]: a value of a small enum told by the name both front ends
//! give it.

/// The value of `all` whose name is `text` (trimmed, ASCII
/// case-insensitive).
///
/// # Errors
/// No value has that name: "unknown WHAT (expected one of ...)".
pub(crate) fn by_name<T: Copy>(
    all: &[T],
    name: fn(T) -> &'static str,
    text: &str,
    what: &str,
) -> Result<T, String> {
    all.iter()
        .copied()
        .find(|&v| name(v).eq_ignore_ascii_case(text.trim()))
        .ok_or_else(|| {
            let names: Vec<&str> = all.iter().map(|&v| name(v)).collect();
            format!("unknown {what} (expected one of {})", names.join(", "))
        })
}
