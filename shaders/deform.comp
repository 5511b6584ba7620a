#version 460
#extension GL_GOOGLE_include_directive : require
// Morphing and skinning: one invocation per vertex of one deformed object (a dispatch
// per object, its offsets in the push constants). The rest vertex is morphed (plus each
// target's displacements times its weight), then, for a skinned object, placed by the
// weighted sum of its joints' matrices (world · inverse bind): the position by the sum,
// the normal by the inverse transpose of its linear part, the tangent by the linear
// part, both brought back to unit length (below). A morphed object that is not skinned stays in its own space
// (its transform places it); a skinned one is written in world space (its transform is
// the identity). The posed vertex is written where the passes that draw the object read
// its first vertex stream. combustion_scene::motion::pose_vertex is the same on the CPU
// (which normalises).
#include "gpu_types.glsl"
#include "bindings/deform.glsl"  // set 0: see combustion_renderer::bindings::DEFORM

layout(local_size_x = 64) in;

layout(push_constant) uniform DeformPush {
    // x: the object's first rest vertex; y: its vertex count; z: its first posed vertex;
    // w: its first target displacement (in vec4s: 3 per vertex per target).
    uvec4 vertices;
    // x: its target count; y: its first weight; z: its skin's first joint matrix, or
    // 0xffffffff when it is not skinned; w: unused.
    uvec4 deform;
} push;

const uint FLOATS_PER_VERTEX = 12u;  // GpuVertex: position, normal, tangent, uv

void main() {
    uint v = gl_GlobalInvocationID.x;
    if (v >= push.vertices.y) {
        return;
    }
    uint rest = (push.vertices.x + v) * FLOATS_PER_VERTEX;
    vec3 position = vec3(rest_vertices[rest], rest_vertices[rest + 1], rest_vertices[rest + 2]);
    vec3 normal = vec3(rest_vertices[rest + 3], rest_vertices[rest + 4], rest_vertices[rest + 5]);
    vec3 tangent = vec3(rest_vertices[rest + 6], rest_vertices[rest + 7], rest_vertices[rest + 8]);
    for (uint t = 0u; t < push.deform.x; ++t) {
        float w = morph_weights[push.deform.y + t];
        if (w == 0.0) {
            continue;
        }
        uint d = push.vertices.w + (t * push.vertices.y + v) * 3u;
        position += w * morph_displacements[d].xyz;
        normal += w * morph_displacements[d + 1u].xyz;
        tangent += w * morph_displacements[d + 2u].xyz;
    }
    if (push.deform.z != 0xffffffffu) {
        uvec2 range = influence_ranges[push.vertices.x + v];
        mat4 sum = mat4(0.0);
        for (uint i = range.x; i < range.x + range.y; ++i) {
            uvec2 influence = influences[i];
            sum += uintBitsToFloat(influence.y) * joint_matrices[push.deform.z + influence.x];
        }
        if (range.y > 0u) {
            mat3 linear = mat3(sum);
            position = (sum * vec4(position, 1.0)).xyz;
            // The inverse transpose up to a positive factor (normals are normalised
            // later): the cofactor matrix, signed by the determinant. Unlike inverse(),
            // it is finite for a singular sum (a joint scaled to 0 to hide a part).
            mat3 cofactor = mat3(cross(linear[1], linear[2]), cross(linear[2], linear[0]),
                                 cross(linear[0], linear[1]));
            vec3 skinned = (determinant(linear) < 0.0 ? -1.0 : 1.0) * (cofactor * normal);
            // A vertex collapsed to a point (every joint of it scaled to 0) keeps its
            // normal: its triangles shrink away, but one that still has area needs a
            // direction at each corner.
            normal = dot(skinned, skinned) > 0.0 ? skinned : normal;
            tangent = linear * tangent;
        }
    }
    // Unit length, as the rest vertices are: the passes interpolate normals and tangents
    // across a triangle before normalising, so their lengths must not vary (a blend of
    // joints scales them). Vectors already unit to 1e-6 are kept bit for bit, so a pose
    // that changes nothing draws the rest mesh exactly.
    float n2 = dot(normal, normal);
    if (n2 > 0.0 && abs(n2 - 1.0) > 2e-6) {
        normal *= inversesqrt(n2);
    }
    float t2 = dot(tangent, tangent);
    if (t2 > 0.0 && abs(t2 - 1.0) > 2e-6) {
        tangent *= inversesqrt(t2);
    }
    uint posed = (push.vertices.z + v) * FLOATS_PER_VERTEX;
    posed_vertices[posed] = position.x;
    posed_vertices[posed + 1] = position.y;
    posed_vertices[posed + 2] = position.z;
    posed_vertices[posed + 3] = normal.x;
    posed_vertices[posed + 4] = normal.y;
    posed_vertices[posed + 5] = normal.z;
    posed_vertices[posed + 6] = tangent.x;
    posed_vertices[posed + 7] = tangent.y;
    posed_vertices[posed + 8] = tangent.z;
    posed_vertices[posed + 9] = rest_vertices[rest + 9];
    posed_vertices[posed + 10] = rest_vertices[rest + 10];
    posed_vertices[posed + 11] = rest_vertices[rest + 11];
}
