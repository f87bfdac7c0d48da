# test_install runs `cmake --install` of this build tree: every installed tool must be built.
target_compile_definitions(${target} PRIVATE CANOPY_CMAKE_COMMAND="${CMAKE_COMMAND}"
                                             CANOPY_BUILD_DIR="${CMAKE_BINARY_DIR}")
add_dependencies(${target} ${canopy_tools})
