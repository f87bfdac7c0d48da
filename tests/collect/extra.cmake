# The sparse-tile test runs the whole class-level chain.
add_dependencies(${target} detect classify score)
# collect::kClassDensity is checked against classify's default --min-density.
target_link_libraries(${target} PRIVATE canopy_classify_lib)
