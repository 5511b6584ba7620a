// What a material says of the surface at one point, its factors times its textures
// times the vertex colour: the one body of this rule for every pass that shades the
// scene's objects — rasterised fragments (material_surface.glsl: the G-buffer and forward
// passes) and a path's hits (path_trace.glsl). The includer defines how a slot's texture
// is read: MATERIAL_TEXTURE(sampler, uv, index, slot) — `sampler` and `uv` the raster's
// (its set 1 binding and interpolated coordinates), `index` the texture-array index
// (≥ 0 where the slot is used) and `slot` the slot's number in
// combustion_scene::TextureSlot::ALL order (for a lookup of its own) — and the name of
// the function it gets, MATERIAL_SURFACE_FUNCTION; then undefines both. A shader may
// include it once per way of reading textures (the forward pass: its fragments', and its
// rays' hits). Needs gpu_types.glsl.
#ifndef MATERIAL_TEXTURE
#error "MATERIAL_TEXTURE(sampler, uv, index, slot) must be defined before material_surface_at.glsl"
#endif
#ifndef MATERIAL_SURFACE_FUNCTION
#error "MATERIAL_SURFACE_FUNCTION must be defined before material_surface_at.glsl"
#endif

#ifndef COMBUSTION_MATERIAL_SURFACE_AT_GLSL
#define COMBUSTION_MATERIAL_SURFACE_AT_GLSL

// What a material says of a surface point, factors times textures times the vertex
// colour.
struct MaterialSurface {
    vec3 base_color;  // linear
    float alpha;      // the base colour factor's, texture's and vertex colour's alpha
    float metalness;
    float roughness;  // perceptual
    float anisotropy; // strength
    vec3 normal;      // unit shading normal (normal map applied; reversed on back faces)
    vec3 direction;   // unit anisotropy direction, in the plane of `normal`
    vec3 emissive;    // emitted radiance (EMISSIVE variant; 0 otherwise)
    float occlusion;  // glTF occlusion (OCCLUSION variant; 1 otherwise)
    // KHR_materials_clearcoat (CLEARCOAT variant; weight 0 otherwise): the coat's weight,
    // perceptual roughness and unit normal (its own normal map applied to the geometry's
    // normal, not the base's normal map; reversed on back faces).
    float clearcoat;
    float clearcoat_roughness;
    vec3 clearcoat_normal;
    // KHR_materials_sheen (SHEEN variant; black otherwise): its linear colour and
    // perceptual roughness.
    vec3 sheen_color;
    float sheen_roughness;
    // KHR_materials_iridescence (IRIDESCENCE variant; 0 otherwise): the thin film's
    // weight and thickness in nm (0: no film).
    float film_weight;
    float film_thickness_nm;
    // KHR_materials_specular (SPECULAR variant; 1 and 1 otherwise): the dielectric's
    // specular factor and its linear colour.
    float specular_factor;
    vec3 specular_color;
    // KHR_materials_transmission and _volume (TRANSMISSION variant; 0 otherwise): the
    // transmission factor × its texture's R, the thickness factor × its texture's G (in
    // the mesh's units).
    float transmission;
    float thickness;
};

// A tangent-space normal map's texel (glTF convention: RGB mapped to [−1, 1]), its x
// and y scaled by `scale`, in `frame` (tangent, bitangent, normal); `fallback` where the
// result is degenerate.
vec3 normal_mapped(vec4 texel, float scale, mat3 frame, vec3 fallback) {
    vec3 m = texel.xyz * 2.0 - 1.0;
    m.xy *= scale;
    vec3 mapped = frame * m;
    return dot(mapped, mapped) > 1e-20 ? normalize(mapped) : fallback;
}

#endif

// The surface `material` makes at a point of interpolated unit normal `n` (towards the
// side seen: reversed on a back face), tangent `tangent` (xyz; w the bitangent's sign),
// vertex colour `color` (white without one) and texture coordinates `uvs` (sets 0 and 1,
// for a MATERIAL_TEXTURE that maps them itself).
MaterialSurface MATERIAL_SURFACE_FUNCTION(GpuMaterial material, vec3 n, vec4 tangent, vec4 color, vec4 uvs) {
    ivec4 tex0 = material.textures_base_mr_normal_occlusion;
    ivec4 tex1 = material.textures_emissive_anisotropy_specular;
    MaterialSurface s;
    float strength = material.roughness_anisotropy_ior.y;
    // The tangent frame, where a normal map or anisotropy reads it — or always, for an
    // includer that reads `direction` on isotropic surfaces too (MATERIAL_SURFACE_
    // DIRECTION_ALWAYS; the G-buffer stores none for them). Without it the normal is the
    // interpolated one and `direction` is 0. On lavapipe the tangent frame's few dozen
    // operations per 4×4 block are measurable where triangles are a few pixels large.
#ifdef MATERIAL_SURFACE_DIRECTION_ALWAYS
    bool framed = true;
#else
    bool framed = tex0.z >= 0 || strength != 0.0;
#ifdef CLEARCOAT
    framed = framed || material.textures_clearcoat.z >= 0;
#endif
#endif
    vec3 t = vec3(0.0);
    vec3 b = vec3(0.0);
    // The geometry's frame, before the base's normal map: the coat's.
    mat3 geometry_frame = mat3(vec3(0.0), vec3(0.0), n);
    if (framed) {
        t = tangent.xyz - n * dot(n, tangent.xyz);
        if (!(dot(t, t) > 1e-20) || any(isnan(t))) {
            vec3 unused;
            orthonormal_basis(n, t, unused);
        }
        t = normalize(t);
        b = cross(n, t) * (tangent.w < 0.0 ? -1.0 : 1.0);
        geometry_frame = mat3(t, b, n);

        // Normal map (tangent space, glTF convention), scaled in x and y.
        if (tex0.z >= 0) {
            n = normal_mapped(MATERIAL_TEXTURE(normal_texture, UV_NORMAL, tex0.z, 2u),
                              material.emissive_normal_scale.a, geometry_frame, n);
            t = normalize(t - n * dot(n, t));
            b = cross(n, t) * (tangent.w < 0.0 ? -1.0 : 1.0);
        }
    }

    vec4 base = vec4(material.base_color_metalness.rgb, material.alpha_cutoff.x);
    if (tex0.x >= 0) {
        base *= MATERIAL_TEXTURE(base_color_texture, UV_BASE_COLOR, tex0.x, 0u);
    }
    base *= color;
    vec4 metal_rough = tex0.y >= 0
        ? MATERIAL_TEXTURE(metallic_roughness_texture, UV_METALLIC_ROUGHNESS, tex0.y, 1u)
        : vec4(1.0);
    // glTF: G = roughness, B = metalness
    s.base_color = base.rgb;
    s.alpha = base.a;
    s.metalness = material.base_color_metalness.a * metal_rough.b;
    s.roughness = material.roughness_anisotropy_ior.x * metal_rough.g;

    // Anisotropy (KHR_materials_anisotropy): direction in tangent space from the texture's
    // RG (or +x), rotated by the material's rotation; strength × the texture's B.
    vec2 along = vec2(1.0, 0.0);
    if (tex1.y >= 0) {
        vec3 a = MATERIAL_TEXTURE(anisotropy_texture, UV_ANISOTROPY, tex1.y, 5u).rgb;
        along = a.rg * 2.0 - 1.0;
        strength *= a.b;
    }
    s.anisotropy = strength;
    s.normal = n;
    // An isotropic surface's lobe is the same about any direction in its plane: the
    // tangent serves, and the rotation is not evaluated (on lavapipe a branch no lane
    // takes costs nothing: the G-buffer pass of builtin:grid-7x7, docs/performance.md).
    s.direction = t;
    if (strength != 0.0) {
        float rotation = material.roughness_anisotropy_ior.z;
        float c = cos(rotation), sn = sin(rotation);
        along = vec2(c * along.x - sn * along.y, sn * along.x + c * along.y);
        vec3 direction = along.x * t + along.y * b;
        if (dot(direction, direction) > 1e-20) {
            s.direction = normalize(direction);
        }
    }

    s.emissive = vec3(0.0);
#ifdef EMISSIVE
    s.emissive = material.emissive_normal_scale.rgb;
    if (tex1.x >= 0) {
        s.emissive *= MATERIAL_TEXTURE(emissive_texture, UV_EMISSIVE, tex1.x, 4u).rgb;
    }
#endif
    // glTF occlusion: 1 + strength · (R − 1), from the texture's red channel.
    s.occlusion = 1.0;
#ifdef OCCLUSION
    if (tex0.w >= 0) {
        float occlusion_strength = uintBitsToFloat(material.diffuse_model_flags.z);
        s.occlusion = 1.0 + occlusion_strength * (MATERIAL_TEXTURE(occlusion_texture, UV_OCCLUSION, tex0.w, 3u).r - 1.0);
    }
#endif
    s.clearcoat = 0.0;
    s.clearcoat_roughness = 0.0;
    s.clearcoat_normal = geometry_frame[2];
#ifdef CLEARCOAT
    // KHR_materials_clearcoat: weight × R of its texture, roughness × G of its own, the
    // coat's normal map in the geometry's tangent frame, scaled in x and y.
    ivec4 tex2 = material.textures_clearcoat;
    s.clearcoat = material.clearcoat.x;
    if (tex2.x >= 0) {
        s.clearcoat *= MATERIAL_TEXTURE(clearcoat_texture, UV_CLEARCOAT, tex2.x, 10u).r;
    }
    s.clearcoat_roughness = material.clearcoat.y;
    if (tex2.y >= 0) {
        s.clearcoat_roughness *= MATERIAL_TEXTURE(clearcoat_roughness_texture, UV_CLEARCOAT_ROUGHNESS, tex2.y, 11u).g;
    }
    if (tex2.z >= 0) {
        s.clearcoat_normal = normal_mapped(MATERIAL_TEXTURE(clearcoat_normal_texture, UV_CLEARCOAT_NORMAL, tex2.z, 12u),
                                           material.clearcoat.w, geometry_frame,
                                           s.clearcoat_normal);
    }
#endif
    s.sheen_color = vec3(0.0);
    s.sheen_roughness = 0.0;
#ifdef SHEEN
    // KHR_materials_sheen: colour × its texture's RGB (sRGB, decoded by the sampler's
    // format), roughness × its texture's A.
    ivec4 tex3 = material.textures_sheen;
    s.sheen_color = material.sheen.rgb;
    if (tex3.x >= 0) {
        s.sheen_color *= MATERIAL_TEXTURE(sheen_color_texture, UV_SHEEN_COLOR, tex3.x, 13u).rgb;
    }
    s.sheen_roughness = material.sheen.a;
    if (tex3.y >= 0) {
        s.sheen_roughness *= MATERIAL_TEXTURE(sheen_roughness_texture, UV_SHEEN_ROUGHNESS, tex3.y, 14u).a;
    }
#endif
    s.film_weight = 0.0;
    s.film_thickness_nm = 0.0;
#ifdef IRIDESCENCE
    // KHR_materials_iridescence: the factor × its texture's R; the thickness from the
    // minimum (z) to the maximum (w) by its texture's G, the maximum without one.
    ivec4 tex4 = material.textures_film;
    s.film_weight = material.film.x;
    if (tex4.x >= 0) {
        s.film_weight *= MATERIAL_TEXTURE(iridescence_texture, UV_IRIDESCENCE, tex4.x, 15u).r;
    }
    s.film_thickness_nm = material.film.w;
    if (tex4.y >= 0) {
        s.film_thickness_nm = mix(material.film.z, material.film.w,
                                  MATERIAL_TEXTURE(iridescence_thickness_texture, UV_IRIDESCENCE_THICKNESS, tex4.y, 16u).g);
    }
#endif
    s.specular_factor = 1.0;
    s.specular_color = vec3(1.0);
#ifdef SPECULAR
    // KHR_materials_specular: the factor × its texture's A, the colour × its colour
    // texture's RGB (sRGB, decoded by the sampler's format).
    s.specular_factor = material.specular.a;
    if (tex1.z >= 0) {
        s.specular_factor *= MATERIAL_TEXTURE(specular_texture, UV_SPECULAR, tex1.z, 6u).a;
    }
    s.specular_color = material.specular.rgb;
    if (tex1.w >= 0) {
        s.specular_color *= MATERIAL_TEXTURE(specular_color_texture, UV_SPECULAR_COLOR, tex1.w, 7u).rgb;
    }
#endif
    s.transmission = 0.0;
    s.thickness = 0.0;
#ifdef TRANSMISSION
    ivec4 tex5 = material.textures_transmission_thickness;
    s.transmission = material.transmission_thickness.x;
    if (tex5.x >= 0) {
        s.transmission *= MATERIAL_TEXTURE(transmission_texture, UV_TRANSMISSION, tex5.x, 8u).r;
    }
    s.thickness = material.transmission_thickness.y;
    if (tex5.y >= 0) {
        s.thickness *= MATERIAL_TEXTURE(thickness_texture, UV_THICKNESS, tex5.y, 9u).g;
    }
#endif
    return s;
}

#undef MATERIAL_TEXTURE
#undef MATERIAL_SURFACE_FUNCTION
