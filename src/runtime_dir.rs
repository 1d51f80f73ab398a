//! A private `XDG_RUNTIME_DIR` for the GPU commands when none is set.
//!
//! Creating a Vulkan instance with the Wayland surface extension (wgpu
//! enables every surface extension it finds) makes Mesa's device-selection
//! layer (`VK_LAYER_MESA_device_select`) look for a Wayland compositor to
//! pick the GPU that drives the display: it calls `wl_display_connect`,
//! and libwayland prints "error: XDG_RUNTIME_DIR is invalid or not set in
//! the environment." when that variable is unset, on every headless run,
//! although nothing failed. Without `XDG_RUNTIME_DIR` no compositor can be
//! reached anyway, so pointing the variable at an empty private directory
//! changes nothing but the message: the connection fails quietly and the
//! layer chooses as it would have.

use std::path::PathBuf;

/// The directory set as `XDG_RUNTIME_DIR`, removed when dropped.
pub struct PrivateRuntimeDir(PathBuf);

impl Drop for PrivateRuntimeDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir(&self.0);
    }
}

/// Sets `XDG_RUNTIME_DIR` to a new empty directory (mode 0700) when it is
/// unset or not absolute (what libwayland rejects); `None` when it is set
/// or no directory can be made.
///
/// Call it before any thread starts: it changes the process environment.
pub fn ensure_runtime_dir() -> Option<PrivateRuntimeDir> {
    let set = std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|v| PathBuf::from(v).is_absolute());
    if set {
        return None;
    }
    let dir = std::env::temp_dir().join(format!("shlight-runtime-{}", std::process::id()));
    let mut builder = std::fs::DirBuilder::new();
    #[cfg(unix)]
    std::os::unix::fs::DirBuilderExt::mode(&mut builder, 0o700);
    builder.create(&dir).ok()?;
    let dir = std::path::absolute(&dir).unwrap_or(dir);
    // SAFETY: called from `main` before the command runs, while the process
    // has a single thread, so no other thread reads the environment.
    unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
    Some(PrivateRuntimeDir(dir))
}
