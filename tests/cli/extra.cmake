# test_cli runs the tool binaries (strict options, range checks, outputs, multi-output
# atomicity) and writes PNGs with libpng to truncate them for `figures grid`.
find_package(PNG REQUIRED)
target_link_libraries(${target} PRIVATE PNG::PNG)
add_dependencies(${target} addnoise fitvox cocone ncut gmatch report figures pcd2ply)

# Bad data inputs to every tool (tests/cli/bad_inputs.sh; hardening.md, "Bad inputs, every tool"):
# exit 1, the file and the problem named, the output untouched, bounded memory, no crash.
add_test(NAME cli_bad_inputs COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli/bad_inputs.sh
                                     ${CMAKE_BINARY_DIR}/bin ${CMAKE_SOURCE_DIR})
set_tests_properties(cli_bad_inputs PROPERTIES TIMEOUT 900)
