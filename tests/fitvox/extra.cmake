# test_fitvox also checks that our samples load in PCL and that PCL-written clouds load here.
# Debian 12: VTK's config (pulled in by PCLConfig) names MPI::MPI_C, which only exists when
# the C language is enabled and MPI was looked up (project() enables CXX only).
if(NOT TARGET MPI::MPI_C)
  enable_language(C)
  find_package(MPI QUIET COMPONENTS C)
endif()
find_package(PCL 1.10 REQUIRED COMPONENTS common io)
target_include_directories(${target} SYSTEM PRIVATE ${PCL_INCLUDE_DIRS})
target_compile_definitions(${target} PRIVATE ${PCL_DEFINITIONS})
target_link_libraries(${target} PRIVATE ${PCL_LIBRARIES})
