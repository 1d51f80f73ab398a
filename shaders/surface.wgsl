// A glTF scene's surfaces lit as mesh.wgsl lights a mesh (shaders/README.md),
// the albedo from each fragment's material (material.wgsl):
//
// MODE_SH: albedo/pi E(n), E the SH irradiance at the normal seen; on a
// lightmapped scene's baked instances (frame.lightmap set, the instance's
// scaleOffset not 0), E the lightmap's (lightmap.wgsl) at the normal seen.
// MODE_PRT: the vertex's transferred radiance per unit albedo (the renderer
// uploads the transfer divided by the albedo it was baked with, vertex by
// vertex), interpolated, times the fragment's albedo, plus the vertex's
// static exit radiance (the scene's lights and emission, its albedo already
// in it; zero without a static term), interpolated; the scene is then
// drawn flattened, one vertex per world vertex, so the vertex index finds
// its transfer.
// MODE_NORMALS: the unit normal seen, as the colour.

@vertex
fn vs_surface(in: SurfaceVertexIn, @builtin(vertex_index) v: u32) -> SurfaceVertexOut {
    var out = surface_vertex(in);
    if frame.mode == MODE_PRT {
        out.prt = prt_radiance(v);
        if frame.prt_static != 0u {
            out.prt_static = static_radiance(v);
        }
    }
    return out;
}

@fragment
fn fs_surface(in: SurfaceVertexOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let albedo = surface_albedo(in);
    let n = surface_normal(in.normal, front);
    switch frame.mode {
        case MODE_NORMALS: {
            return vec4<f32>(n, 1.0);
        }
        case MODE_PRT: {
            var radiance = in.prt * albedo;
            if frame.prt_static != 0u {
                radiance = radiance + in.prt_static;
            }
            return finish(radiance);
        }
        default: {
            if frame.lightmap != LIGHTMAP_NONE && in.lightmap_baked == 1u {
                return finish(albedo / SH_PI * lightmap_irradiance(in.lightmap_uv, n));
            }
            let e = sh_reconstruct(n, frame.irradiance_band);
            return finish(albedo / SH_PI * e);
        }
    }
}
