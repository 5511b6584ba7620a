# CMake settings for the C++ build of shaderc, glslang and SPIRV-Tools that the shaderc
# crate runs (its build-from-source feature); .cargo/config.toml points cmake-rs at this
# file through CMAKE_TOOLCHAIN_FILE. That build is most of a cold `cargo build` (README,
# "Build cost"), and what it produces only compiles the project's GLSL, at start-up and
# then from the SPIR-V cache, so it is built for build time:
#  - -O1, not CMake's Release -O3: the C++ compiles in about half the time
#    (glslang's ParseHelper.cpp 10.0 s -> 5.4 s), and a built-in scene's shaders compile in
#    about the same time (README, "Build cost");
#  - none of shaderc's examples, which the crate does not link (its executable, glslc,
#    stays: shaderc's install step names it even when asked to skip executables);
#  - the libraries nothing links built empty (scripts/shaderc-unlinked-libraries.cmake).
# Cache entries set here are taken before CMake's own defaults, which do not replace them.
set(CMAKE_C_FLAGS_RELEASE "-O1 -DNDEBUG" CACHE STRING "C flags of shaderc's Release build")
set(CMAKE_CXX_FLAGS_RELEASE "-O1 -DNDEBUG" CACHE STRING "C++ flags of shaderc's Release build")
set(SHADERC_SKIP_EXAMPLES ON CACHE BOOL "the shaderc crate links the library only")
set(CMAKE_PROJECT_native-shaderc_INCLUDE "${CMAKE_CURRENT_LIST_DIR}/shaderc-unlinked-libraries.cmake"
  CACHE FILEPATH "empties the libraries of shaderc's build that the crate does not link")
