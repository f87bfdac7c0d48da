# The sparse-tile test runs the whole class-level chain.
add_dependencies(${target} detect classify score)
