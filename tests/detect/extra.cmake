# test_detect runs the chain (rangetrace | fitvox | cocone | ncut | gmatch) on a candidate, and
# detect through the stage runner as make does.
add_dependencies(${target} rangetrace fitvox cocone ncut gmatch stagerun)
target_link_libraries(${target} PRIVATE nlohmann_json::nlohmann_json)
target_include_directories(${target} PRIVATE ${CMAKE_SOURCE_DIR}/tests)
target_link_libraries(${target} PRIVATE canopy_candtruth_lib)
add_dependencies(${target} candtruth)
