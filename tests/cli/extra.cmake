# test_cli runs the tool binaries (strict options, range checks, outputs, multi-output
# atomicity) and writes PNGs with libpng to truncate them for `figures grid`.
find_package(PNG REQUIRED)
target_link_libraries(${target} PRIVATE PNG::PNG)
add_dependencies(${target} addnoise fitvox cocone ncut gmatch report figures pcd2ply)
