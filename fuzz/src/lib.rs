//! What the fuzz targets share: the limits they read with, so that
//! `fuzz/run.sh`'s `-rss_limit_mb` and `-timeout` hold what
//! docs/limits.md promises for them.

/// The pixel limit the image targets read with (`ReadOptions::max_pixels`):
/// 2^22 (2048 x 2048). docs/limits.md bounds a read's memory by
/// 64 bytes a pixel of this limit plus a few times the file's size, so
/// 256 MiB here, well inside the targets' 2048 MiB RSS limit.
pub const MAX_PIXELS: usize = 1 << 22;

/// The mesh limits the mesh targets read with (`LoadOptions`): 2^20
/// vertices and 2^21 triangles, so that docs/limits.md's bound (about 40
/// bytes a vertex and 12 a triangle, plus a few times the file's size)
/// stays far inside the targets' RSS limit; and glTF textures of 2^18
/// pixels (16 of them, 4 bytes a pixel: 16 MiB, and the decoder's 32
/// bytes a pixel of one: 8 MiB).
pub const MESH_LIMITS: shlight_mesh::LoadOptions = shlight_mesh::LoadOptions {
    max_vertices: 1 << 20,
    max_triangles: 1 << 21,
    max_texture_pixels: 1 << 18,
};

/// Installs the targets' panic hook (call it from `fuzz_target!`'s `init`).
///
/// A panic in shlight's own code (its location is in a `crates/shlight-*`
/// file; indexing and `unwrap` report their caller) aborts at once: that
/// is a finding. A panic elsewhere (a dependency's decoder) is printed the
/// first time at each location and left to unwind, so that the guard a
/// reader puts around that dependency (`catch_unwind` in shlight-io's
/// decoders) can turn it into an error, as it does for a user; a panic
/// that no guard catches still aborts, because libfuzzer-sys aborts when
/// one leaves the target.
pub fn abort_on_shlight_panics() {
    use std::collections::HashSet;
    use std::sync::Mutex;

    static SEEN: Mutex<Option<HashSet<String>>> = Mutex::new(None);
    // libfuzzer-sys's hook: prints the panic and aborts.
    let abort = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let location = info.location().map(|l| l.to_string()).unwrap_or_default();
        if location.contains("crates/shlight-") {
            abort(info);
        }
        let mut seen = SEEN.lock().unwrap_or_else(|e| e.into_inner());
        if seen
            .get_or_insert_with(HashSet::new)
            .insert(location.clone())
        {
            eprintln!("dependency panic, left to shlight's guard: {info}");
        }
    }));
}
