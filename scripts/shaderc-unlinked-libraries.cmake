# Included after shaderc-sys's top-level project() (scripts/shaderc-toolchain.cmake names it
# in CMAKE_PROJECT_native-shaderc_INCLUDE). The crate builds and installs all of shaderc's
# CMake project but links only libshaderc_combined.a: SPIRV-Tools' core built a second
# time as a shared library (its CMake always builds one), and SPIRV-Tools' reduce, lint
# and diff libraries, are compiled and installed for nothing. Once every target exists
# (a deferred call at the end of the top-level CMakeLists), each of those gets one empty
# source file in place of its own, so it is still built and installed, empty, and its
# 109 of the build's 375 object files are not compiled (README, "Build cost").
if(CMAKE_VERSION VERSION_GREATER_EQUAL 3.19)
  function(combustion_empty_unlinked_libraries)
    foreach(library SPIRV-Tools-shared SPIRV-Tools-reduce SPIRV-Tools-lint SPIRV-Tools-diff)
      if(TARGET ${library})
        set_property(TARGET ${library} PROPERTY SOURCES
          "${CMAKE_CURRENT_FUNCTION_LIST_DIR}/shaderc-empty-library.cpp")
      endif()
    endforeach()
  endfunction()
  cmake_language(DEFER CALL combustion_empty_unlinked_libraries)
endif()
