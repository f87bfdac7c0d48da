# The simulator's library is canopy_sim (sim/CMakeLists.txt), not a stage's canopy_sim_lib.
target_link_libraries(${target} PRIVATE canopy_sim)
