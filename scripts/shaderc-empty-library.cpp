// The one source of the shaderc build's libraries that nothing links
// (scripts/shaderc-unlinked-libraries.cmake): intentionally empty.
