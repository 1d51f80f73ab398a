//! [`SceneHooks`]: what a scene's reading and drawing tell the front end
//! as they go.

/// Callbacks for progress, warnings and notes, each given one line for
/// the user (naming the file it is about).
#[derive(Clone, Copy)]
pub struct SceneHooks<'a> {
    /// Told what starts next (`"reading the mesh"`, `"opening the GPU"`,
    /// ...), for a progress line.
    pub progress: &'a dyn Fn(&str),
    /// Given each warning: something is probably not what the user meant
    /// (a volume baked in another scene, negative texels in a map).
    pub warn: &'a dyn Fn(&str),
    /// Given each note: what was read and how it is shaded (a volume's
    /// probes, an lmax clipped, the lights an encoding kept apart).
    pub note: &'a dyn Fn(&str),
}

impl Default for SceneHooks<'static> {
    /// Everything dropped.
    fn default() -> Self {
        Self {
            progress: &|_| {},
            warn: &|_| {},
            note: &|_| {},
        }
    }
}

impl std::fmt::Debug for SceneHooks<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("SceneHooks")
    }
}
