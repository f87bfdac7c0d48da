# test_noise.cpp runs fitvox's resampling before the reconstruction.
target_link_libraries(${target} PRIVATE canopy_fitvox_lib)
