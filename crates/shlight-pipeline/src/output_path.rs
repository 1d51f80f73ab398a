//! Output paths of every job: never over an input, directories by name.

use std::path::Path;

use crate::{PipelineError, Result};

/// Whether an output path names a directory: it is one, or ends with a
/// separator.
#[must_use]
pub fn names_dir(p: &Path) -> bool {
    p.is_dir()
        || p.as_os_str()
            .to_string_lossy()
            .ends_with(std::path::is_separator)
}

/// Refuses `output` when it is one of `inputs` (the same file by path, link
/// or inode).
///
/// # Errors
/// `output` is an input, naming both.
pub fn refuse_overwriting<P: AsRef<Path>>(output: &Path, inputs: &[P]) -> Result<()> {
    for input in inputs {
        let input = input.as_ref();
        if same_file(output, input) {
            return Err(PipelineError::new(format!(
                "{}: refusing to write over the input {}",
                output.display(),
                input.display()
            )));
        }
    }
    Ok(())
}

fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
        use std::os::unix::fs::MetadataExt;
        return x.dev() == y.dev() && x.ino() == y.ino();
    }
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(x), Ok(y)) => x == y,
        _ => match (std::path::absolute(a), std::path::absolute(b)) {
            (Ok(x), Ok(y)) => x == y,
            _ => false,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_output_over_an_input_is_refused_by_any_path() {
        let dir = std::env::temp_dir().join(format!("shlight-output-path-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let input = dir.join("in.exr");
        std::fs::write(&input, b"x").unwrap();
        let other = dir.join("out.json");
        let dotted = dir.join(".").join("in.exr");
        assert!(refuse_overwriting(&dotted, std::slice::from_ref(&input)).is_err());
        assert!(refuse_overwriting(&other, std::slice::from_ref(&input)).is_ok());
        #[cfg(unix)]
        {
            let link = dir.join("link.exr");
            let _ = std::fs::remove_file(&link);
            std::os::unix::fs::symlink(&input, &link).unwrap();
            assert!(refuse_overwriting(&link, std::slice::from_ref(&input)).is_err());
        }
        assert!(names_dir(&dir));
        assert!(names_dir(Path::new("not-there/")));
        assert!(!names_dir(&other));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
