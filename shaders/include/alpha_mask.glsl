// The cut-out test of glTF's alphaMode MASK, shared by the G-buffer pass and the shadow
// casters (their ALPHA_MASK pipelines): the surface is absent where alpha (the base colour
// factor's alpha × the base colour texture's alpha, filtered as the sampler says) is below
// alphaCutoff. Needs gpu_types.glsl. docs/gltf.md, "Alpha modes" (why the alpha is not
// raised on coarse mip levels).
#ifndef COMBUSTION_ALPHA_MASK_GLSL
#define COMBUSTION_ALPHA_MASK_GLSL

// Whether `material`'s surface is absent at `uv` (the base colour slot's coordinates).
bool alpha_cut_away(GpuMaterial material, sampler2D base_color, vec2 uv) {
    float alpha = material.alpha_cutoff.x;
    if (material.textures_base_mr_normal_occlusion.x >= 0) {
        alpha *= texture(base_color, uv).a;
    }
    return alpha < material.alpha_cutoff.y;
}

#endif
