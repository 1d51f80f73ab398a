//! Atomic writes: a failed write leaves an existing destination as it was
//! and no temporary file behind.

use std::io;

use shlight_io::{Image, IoErrorKind, WriteOptions, write_atomically, write_image};

use crate::assert_kind;
use crate::util::{TempDir, hdr_image, read};

const OLD: &[u8] = b"old contents\n";

#[test]
fn write_atomically_writes_and_replaces() {
    let dir = TempDir::new("atomic-ok");
    let path = dir.join("out.json");
    write_atomically(&path, |w| w.write_all(b"{}\n")).unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), b"{}\n");
    write_atomically(&path, |w| {
        // Written in pieces, through the buffer.
        for i in 0..10_000 {
            write!(w, "{i} ")?;
        }
        Ok(())
    })
    .unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.starts_with("0 1 2 ") && text.ends_with("9999 "));
    assert_eq!(dir.entries(), ["out.json"]);
}

#[test]
fn failing_writer_leaves_the_old_file() {
    let dir = TempDir::new("atomic-fail");
    let path = dir.join("out.json");
    std::fs::write(&path, OLD).unwrap();
    let result = write_atomically(&path, |w| {
        w.write_all(&[b'x'; 100_000])?;
        Err(io::Error::other("disk on fire"))
    });
    assert_kind!(result, IoErrorKind::Write(_));
    let message = result.unwrap_err().to_string();
    assert_eq!(
        message,
        format!("{}: cannot write the file (disk on fire)", path.display())
    );
    assert_eq!(std::fs::read(&path).unwrap(), OLD);
    assert_eq!(dir.entries(), ["out.json"]);
}

#[test]
fn panicking_writer_leaves_the_old_file() {
    let dir = TempDir::new("atomic-panic");
    let path = dir.join("out.txt");
    std::fs::write(&path, OLD).unwrap();
    let result = std::panic::catch_unwind(|| {
        let _ = write_atomically(&path, |w| {
            w.write_all(b"partial")?;
            panic!("writer bug");
        });
    });
    assert!(result.is_err());
    assert_eq!(std::fs::read(&path).unwrap(), OLD);
    assert_eq!(dir.entries(), ["out.txt"]);
}

#[test]
fn failed_image_writes_leave_the_old_file() {
    let dir = TempDir::new("atomic-image");
    let path = dir.join("map.exr");
    std::fs::write(&path, OLD).unwrap();

    // No pixels.
    let empty = Image::new(0, 7, vec![]).unwrap();
    for name in ["map.exr", "map.hdr", "map.png"] {
        let target = dir.join(name);
        let result = write_image(&target, &empty, &WriteOptions::default());
        assert_kind!(
            result,
            IoErrorKind::EmptyImage {
                width: 0,
                height: 7
            }
        );
    }
    assert_eq!(std::fs::read(&path).unwrap(), OLD);
    assert_eq!(dir.entries(), ["map.exr"]);

    // The destination is a directory: the whole file is written, then the
    // rename fails; the temporary file must go.
    let sub = dir.join("sub.png");
    std::fs::create_dir(&sub).unwrap();
    std::fs::write(sub.join("keep"), OLD).unwrap();
    let result = write_image(&sub, &hdr_image(16, 8), &WriteOptions::default());
    assert_kind!(result, IoErrorKind::Write(_));
    assert!(
        result
            .unwrap_err()
            .to_string()
            .starts_with(&sub.display().to_string())
    );
    assert!(sub.is_dir());
    assert_eq!(std::fs::read(sub.join("keep")).unwrap(), OLD);
    assert_eq!(dir.entries(), ["map.exr", "sub.png"]);

    // A directory that does not exist.
    let result = write_image(
        &dir.join("none/map.exr"),
        &hdr_image(4, 4),
        &WriteOptions::default(),
    );
    assert_kind!(result, IoErrorKind::Write(_));

    // A successful write replaces the old file.
    let image = hdr_image(16, 8);
    write_image(&path, &image, &WriteOptions::default()).unwrap();
    assert_eq!(read(&path).unwrap(), image);
    assert_eq!(dir.entries(), ["map.exr", "sub.png"]);
}

/// A temporary file that cannot be made fails the write: a `Write` error
/// naming the destination, the old file as it was, nothing left behind.
/// The destination's name is 250 bytes, so its temporary name
/// (`.NAME.tmp-PID-N`) passes the 255-byte limit on a file name of Unix
/// file systems: refused for every user, root included, unlike a
/// directory without write permission (below).
#[cfg(unix)]
#[test]
fn temporary_file_that_cannot_be_made_leaves_the_old_file() {
    let dir = TempDir::new("atomic-long-name");
    let name = format!("{}.png", "m".repeat(246));
    assert_eq!(name.len(), 250);
    let path = dir.join(&name);
    std::fs::write(&path, OLD).unwrap();
    let result = write_image(&path, &hdr_image(8, 8), &WriteOptions::default());
    assert_kind!(result, IoErrorKind::Write(_));
    assert!(
        result
            .unwrap_err()
            .to_string()
            .starts_with(&path.display().to_string())
    );
    assert_eq!(std::fs::read(&path).unwrap(), OLD);
    assert_eq!(dir.entries(), [name]);
}

/// A directory without write permission: where the system enforces it the
/// write fails and the old file stays; root (as in many containers and CI
/// machines) may write anyway, and then the write must succeed and leave
/// only the new file. The refusal itself is tested for every user by
/// [`temporary_file_that_cannot_be_made_leaves_the_old_file`].
#[cfg(unix)]
#[test]
fn read_only_directory() {
    use std::os::unix::fs::PermissionsExt;
    let dir = TempDir::new("atomic-read-only");
    let ro = dir.join("ro");
    std::fs::create_dir(&ro).unwrap();
    let path = ro.join("map.png");
    std::fs::write(&path, OLD).unwrap();
    std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o555)).unwrap();
    let probe = ro.join("probe");
    let enforced = std::fs::write(&probe, b"").is_err();
    let _ = std::fs::remove_file(&probe);

    let result = write_image(&path, &hdr_image(8, 8), &WriteOptions::default());
    std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o755)).unwrap();
    if enforced {
        assert_kind!(result, IoErrorKind::Write(_));
        assert_eq!(std::fs::read(&path).unwrap(), OLD);
    } else {
        result.unwrap();
        let back = read(&path).unwrap();
        assert_eq!((back.width(), back.height()), (8, 8));
    }
    let mut names: Vec<_> = std::fs::read_dir(&ro)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    names.sort();
    assert_eq!(names, ["map.png"]);
}
