# The sparse-tile test runs the whole class-level chain.
add_dependencies(${target} detect classify score)
# collect's class groups are checked against classify's taxonomy (class_group, entry_group).
target_link_libraries(${target} PRIVATE canopy_classify_lib)
