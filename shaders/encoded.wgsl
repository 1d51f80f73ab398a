// Shading with an encoding of the light other than plain SH
// (shaders/README.md): dominant lights plus residual SH, ZH3, non-linear
// L1 or an ambient cube. Per fragment, the outgoing radiance
// rho/pi E(R^T n) at the interpolated unit normal n, where E is the
// encoding's irradiance, shlight_irradiance(n: vec3<f32>) -> vec3<f32>,
// and R the rotation the light was turned by (frame.light_from_world is
// R^T: an encoding such as the ambient cube cannot itself be turned, so the
// normal is turned back instead).
//
// shlight_irradiance is the WGSL snippet shlight-format writes for the
// encoding (`shlight project MAP --encoding E --format wgsl`), its
// constants baked in; it is appended to this module, so a new light or
// encoding compiles a new pipeline (shlight-gpu's Renderer::set_encoding).
// The vertex stage is mesh.wgsl's vs_mesh.

@fragment
fn fs_encoded(in: VertexOut) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let unturned = (frame.light_from_world * vec4<f32>(n, 0.0)).xyz;
    let e = shlight_irradiance(unturned);
    return finish(frame.albedo.rgb / SH_PI * e);
}
