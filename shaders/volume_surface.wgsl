// A glTF scene's surfaces lit by an irradiance volume, as volume.wgsl's
// fs_volume lights a mesh: albedo/pi E(p, n) plus the emitted radiance, at
// the fragment's world point and the normal seen, the albedo from the
// fragment's material (material.wgsl).

@vertex
fn vs_volume_surface(in: SurfaceVertexIn) -> SurfaceVertexOut {
    return surface_vertex(in);
}

@fragment
fn fs_volume_surface(
    in: SurfaceVertexOut,
    @builtin(front_facing) front: bool,
) -> @location(0) vec4<f32> {
    let albedo = surface_albedo(in);
    let n = surface_normal(in.normal, front);
    let e = volume_irradiance(in.world, n).rgb;
    return finish(albedo / SH_PI * e + in.emission);
}
