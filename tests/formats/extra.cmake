# Interoperability: files PCL writes load with ours, files we write load in PCL and VTK.
find_package(PCL 1.12 REQUIRED COMPONENTS common io)
find_package(VTK REQUIRED COMPONENTS IOPLY CommonCore CommonDataModel)
target_include_directories(${target} SYSTEM PRIVATE ${PCL_INCLUDE_DIRS})
target_link_libraries(${target} PRIVATE ${PCL_LIBRARIES} VTK::IOPLY VTK::CommonCore VTK::CommonDataModel)
add_dependencies(${target} pcd2ply)
