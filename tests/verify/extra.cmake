# The mismatched-inputs regression segments a foreign mesh with the real ncut.
add_dependencies(${target} ncut)
