#version 460
// Back faces pass, fragment stage (front faces culled): the nearest far side of the
// transmissive volumes at each pixel, its depth (the attachment) and its world-space
// normal as the mesh gives it, facing out of the object. A ray that forward.frag
// refracts into such an object leaves it there (VOLUME variant).

layout(location = 0) in vec3 in_normal;

layout(location = 0) out vec4 out_normal;

void main() {
    out_normal = vec4(normalize(in_normal), 0.0);
}
