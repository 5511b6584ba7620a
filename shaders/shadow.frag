#version 460
// Shadow-caster pass, fragment stage: depth only, nothing written here.
void main() {
}
