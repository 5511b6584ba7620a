// The cut-out test of glTF's alphaMode MASK, shared by the G-buffer pass and the shadow
// casters (their ALPHA_MASK pipelines): the surface is absent where alpha (the base colour
// factor's alpha × the base colour texture's alpha × the vertex colour's alpha) is below
// alphaCutoff. Needs
// gpu_types.glsl. docs/gltf.md, "Alpha modes".
#ifndef COMBUSTION_ALPHA_MASK_GLSL
#define COMBUSTION_ALPHA_MASK_GLSL

// The alpha of mip level `level` of `material`'s base colour texture at `uv`, scaled so
// that the level keeps level 0's coverage (combustion_scene::alpha_mip_scales: 1 on
// level 0, and on every level of an alpha that averages to itself, such as a ramp).
float alpha_on_level(GpuMaterial material, sampler2D base_color, vec2 uv, float level) {
    int l = clamp(int(level), 0, 15);
    return textureLod(base_color, uv, level).a * material.alpha_mip_scales[l >> 2][l & 3];
}

// Whether `material`'s surface is absent at `uv` (the base colour slot's coordinates)
// where the vertex colour's alpha is `vertex_alpha`.
// The texture's alpha is read as the sampler filters it, level by level: each level's
// own (coverage-preserving) scale applied before two levels are blended.
bool alpha_cut_away(GpuMaterial material, sampler2D base_color, vec2 uv, float vertex_alpha) {
    float alpha = material.alpha_cutoff.x * vertex_alpha;
    if (material.textures_base_mr_normal_occlusion.x >= 0) {
        float level = max(textureQueryLod(base_color, uv).x, 0.0);
        if (material.alpha_cutoff.z != 0.0) {
            level = floor(level + 0.5);  // a NEAREST mipmap filter
        }
        float below = floor(level);
        float blend = level - below;
        float a = alpha_on_level(material, base_color, uv, below);
        if (blend > 0.0) {
            a = mix(a, alpha_on_level(material, base_color, uv, below + 1.0), blend);
        }
        alpha *= a;
    }
    return alpha < material.alpha_cutoff.y;
}

#endif
