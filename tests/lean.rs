//! A build without the `gpu` feature: the GPU commands exist, and fail
//! saying which feature they need; everything else still works.

use crate::util::{s, shlight_err, shlight_ok, temp_dir, write_map, write_obj};

#[test]
fn gpu_commands_name_the_feature_they_need() {
    let dir = temp_dir("lean_gpu_commands");
    let (mesh, env) = (dir.join("s.obj"), dir.join("sky.exr"));
    write_obj(&mesh, &shlight_mesh::generate::uv_sphere(1.0, 8, 4));
    write_map(&env, 16, 8, |_, _| [1.0; 3]);
    let out = dir.join("s.png");
    let cases: [(&str, Vec<&str>); 3] = [
        (
            "render-mesh",
            vec!["render-mesh", s(&mesh), "--env", s(&env), "-o", s(&out)],
        ),
        ("view", vec!["view", s(&mesh), "--env", s(&env)]),
        ("project --gpu", vec!["project", s(&env), "--gpu"]),
    ];
    for (command, args) in cases {
        let err = shlight_err(&args);
        assert!(
            err.contains(&format!("{command} needs the gpu feature")),
            "{command}: {err}"
        );
    }
    assert!(!out.exists());
    // The CPU commands are all there.
    shlight_ok(&["project", s(&env), "-o", s(&dir.join("sky.json"))]);
}
