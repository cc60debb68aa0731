# sf_mesh_io: the project's one triangle-mesh type and reader (mesh_io.hpp;
# CGAL's OBJ/OFF/PLY/STL readers and assimp's Collada one, in
# mesh_io.cpp only). Linked by the simulator's
# sf_scenario and by the evaluator's sf_eval; included from sim/CMakeLists.txt,
# or from apps/eval/CMakeLists.txt when the simulator is not built.
if(NOT TARGET sf_mesh_io)
  # The sanitizer build is Debug: CGAL's notice that Release is faster does not concern one file of mesh I/O.
  set(CGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE TRUE CACHE INTERNAL "")
  find_package(CGAL REQUIRED)
  find_package(assimp REQUIRED CONFIG)
  add_library(sf_mesh_io STATIC ${CMAKE_CURRENT_LIST_DIR}/mesh_io.cpp)
  target_include_directories(sf_mesh_io PUBLIC ${CMAKE_CURRENT_LIST_DIR})
  target_link_libraries(sf_mesh_io PUBLIC Eigen3::Eigen PRIVATE CGAL::CGAL assimp::assimp)
  # CGAL's own headers are not warning-clean under -Wpedantic.
  get_target_property(_sf_mesh_cgal_inc CGAL::CGAL INTERFACE_INCLUDE_DIRECTORIES)
  if(_sf_mesh_cgal_inc)
    target_include_directories(sf_mesh_io SYSTEM PRIVATE ${_sf_mesh_cgal_inc})
  endif()
endif()
