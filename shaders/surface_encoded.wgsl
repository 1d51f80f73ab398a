// A glTF scene's surfaces shaded with an encoding of the light other than
// plain SH, as encoded.wgsl shades a mesh: albedo/pi E(R^T n) at the normal
// seen, the albedo from the fragment's material (material.wgsl), E the
// encoding's shlight_irradiance appended to the module. The vertex stage is
// surface.wgsl's vs_surface.

@fragment
fn fs_surface_encoded(
    in: SurfaceVertexOut,
    @builtin(front_facing) front: bool,
) -> @location(0) vec4<f32> {
    let albedo = surface_albedo(in);
    let n = surface_normal(in.normal, front);
    let unturned = (frame.light_from_world * vec4<f32>(n, 0.0)).xyz;
    return finish(albedo / SH_PI * shlight_irradiance(unturned));
}
