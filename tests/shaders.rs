//! Every WGSL file in `shaders/` parses and validates with naga (no GPU),
//! inside the modules the renderer compiles; a broken shader is refused.

use std::collections::BTreeSet;

use shlight_gpu::shaders::{FILES, MODULES};

fn validate(source: &str) -> Result<naga::Module, String> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| e.emit_to_string(source))?;
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .map_err(|e| e.emit_to_string(source))?;
    Ok(module)
}

#[test]
fn every_file_in_shaders_is_compiled_and_as_on_disk() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let on_disk: BTreeSet<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".wgsl"))
        .collect();
    let known: BTreeSet<String> = FILES.iter().map(|(n, _)| n.to_string()).collect();
    assert_eq!(
        on_disk, known,
        "shaders/ and shlight_gpu::shaders::FILES differ"
    );
    for (name, text) in FILES {
        let disk = std::fs::read_to_string(dir.join(name)).unwrap();
        assert_eq!(disk, text, "{name}: the built-in text is stale");
        assert!(
            MODULES.iter().any(|m| m.files.contains(&name)),
            "{name} is in no module"
        );
    }
}

#[test]
fn every_module_validates() {
    for module in MODULES {
        for lmax in 0..=shlight_baked::LIGHT_MAX_LMAX {
            if let Err(e) = validate(&module.source_at(lmax)) {
                panic!(
                    "shader module {} does not validate at lmax {lmax}:\n{e}",
                    module.name
                );
            }
        }
    }
}

#[test]
fn broken_shaders_are_refused() {
    let sh = MODULES.iter().find(|m| m.name == "sh").unwrap().source();
    // A type error: a vec3 returned as f32.
    let type_error = format!("{sh}\nfn broken(d: vec3<f32>) -> f32 {{ return d; }}\n");
    assert!(validate(&type_error).is_err(), "a type error was accepted");
    // A syntax error.
    let syntax_error = sh.replacen("fn sh_count", "fn sh_count(", 1);
    assert!(
        validate(&syntax_error).is_err(),
        "a syntax error was accepted"
    );
    // An unknown function.
    let unknown = format!("{sh}\nfn broken() -> f32 {{ return sh_nothing(1.0); }}\n");
    assert!(
        validate(&unknown).is_err(),
        "an unknown function was accepted"
    );
}

#[test]
fn the_frame_uniform_is_496_bytes_as_the_renderer_writes_it() {
    let mesh = MODULES.iter().find(|m| m.name == "mesh").unwrap().source();
    let module = validate(&mesh).unwrap();
    let span = module
        .types
        .iter()
        .find_map(|(_, t)| match (&t.name, &t.inner) {
            (Some(name), naga::TypeInner::Struct { span, .. }) if name == "Frame" => Some(*span),
            _ => None,
        })
        .expect("struct Frame in scene.wgsl");
    // shlight-gpu's FrameUniform (a unit test there checks its size).
    assert_eq!(span, 496);
}
