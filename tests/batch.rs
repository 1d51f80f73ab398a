//! `shlight project` with several inputs: one output per input in a
//! directory, failures reported per file, no output onto an input.

use crate::util::{read_json, s, shlight, shlight_err, shlight_ok, temp_dir, write_map};

#[test]
fn several_inputs_go_to_a_directory_and_one_failure_fails_the_run_after_the_rest() {
    let dir = temp_dir("batch");
    let a = dir.join("a.exr");
    let b = dir.join("b.exr");
    let bad = dir.join("broken.exr");
    write_map(&a, 32, 16, |_, _| [1.0, 1.0, 1.0]);
    write_map(&b, 64, 32, |x, _| [x as f32, 0.0, 1.0]);
    write_map(&bad, 32, 16, |_, _| [1.0; 3]);
    let bytes = std::fs::read(&bad).unwrap();
    std::fs::write(&bad, &bytes[..bytes.len() / 2]).unwrap();

    let out_dir = dir.join("out/nested");
    let o = shlight(&[
        "project",
        s(&a),
        s(&bad),
        s(&b),
        "-o",
        s(&out_dir),
        "--lmax",
        "3",
    ]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("broken.exr") && err.contains("1 of 3 inputs failed"),
        "{err}"
    );
    assert!(!err.contains("a.exr") && !err.contains("b.exr"), "{err}");
    for (name, width) in [("a", 32), ("b", 64)] {
        let v = read_json(&out_dir.join(format!("{name}.json")));
        assert_eq!(v["lmax"], 3);
        assert_eq!(v["provenance"]["width"], width);
    }
    assert!(!out_dir.join("broken.json").exists());
    assert!(o.stdout.is_empty());

    // All good: success, --format txt gives .txt files, previews go to a directory.
    let txt_dir = dir.join("txt");
    let previews = dir.join("previews");
    shlight_ok(&[
        "project",
        s(&a),
        s(&b),
        "-o",
        s(&txt_dir),
        "--format",
        "txt",
        "--preview",
        s(&previews),
        "--preview-size",
        "32x16",
    ]);
    let table = std::fs::read_to_string(txt_dir.join("b.txt")).unwrap();
    assert!(table.starts_with("# shlight SH radiance"), "{table}");
    for name in ["a", "b"] {
        let img =
            shlight_io::read_image(&previews.join(format!("{name}.png")), &Default::default())
                .unwrap();
        assert_eq!((img.width(), img.height()), (96, 16));
    }
}

#[test]
fn several_inputs_need_a_directory_and_distinct_names() {
    let dir = temp_dir("batch_refused");
    let a = dir.join("a.exr");
    write_map(&a, 32, 16, |_, _| [1.0; 3]);
    std::fs::create_dir_all(dir.join("x")).unwrap();
    let a2 = dir.join("x/a.exr");
    std::fs::copy(&a, &a2).unwrap();

    let err = shlight_err(&["project", s(&a), s(&a2)]);
    assert!(err.contains("-o DIR"), "{err}");
    let out = dir.join("out");
    let err = shlight_err(&["project", s(&a), s(&a2), "-o", s(&out)]);
    assert!(err.contains("would both be written"), "{err}");
    assert!(!out.exists(), "nothing is created for a refused run");
    // -o naming an existing file with several inputs.
    let file = dir.join("file.json");
    std::fs::write(&file, "precious").unwrap();
    let err = shlight_err(&["project", s(&a), s(&a2), "-o", s(&file)]);
    assert!(err.contains("file.json"), "{err}");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "precious");
}

#[test]
fn outputs_never_overwrite_inputs() {
    let dir = temp_dir("batch_self");
    let a = dir.join("a.exr");
    write_map(&a, 32, 16, |_, _| [1.0; 3]);
    let before = std::fs::read(&a).unwrap();
    for args in [
        vec!["project", s(&a), "-o", s(&a)],
        vec!["project", s(&a), "--preview", s(&a)],
    ] {
        let err = shlight_err(&args);
        assert!(
            err.contains("refusing to write over the input"),
            "{args:?}: {err}"
        );
    }
    // The same file by another spelling of its path.
    let other = format!("{}/./a.exr", s(&dir));
    let err = shlight_err(&["project", s(&a), "-o", &other]);
    assert!(err.contains("refusing"), "{err}");
    assert_eq!(std::fs::read(&a).unwrap(), before);
    // One input and -o an existing directory: DIR/NAME.json.
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    shlight_ok(&["project", s(&a), "-o", s(&out)]);
    assert_eq!(read_json(&out.join("a.json"))["lmax"], 2);
}
