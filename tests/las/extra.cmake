# test_las runs the pipeline tools on a rendered scan (test_utm.cpp).
add_dependencies(${target} rangetrace addnoise fitvox cocone ncut gmatch pcd2ply)
