# test_las runs the pipeline tools on a rendered scan (test_utm.cpp).
add_dependencies(${target} rangetrace addnoise fitvox cocone ncut gmatch pcd2ply)
# test_laz.cpp compares every shared real LAZ with its reference LAS when this directory
# (laz/, reference/; see its README) exists, and skips that one test otherwise.
set(CANOPY_REAL_DATA "${CMAKE_SOURCE_DIR}/../shared/data/real" CACHE PATH
    "real LiDAR pairs (laz/ and reference/) for test_las's full LAZ comparison")
target_compile_definitions(${target} PRIVATE CANOPY_REAL_DATA="${CANOPY_REAL_DATA}")
