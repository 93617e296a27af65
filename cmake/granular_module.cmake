# granular_add_module(<name> <export set> SOURCES <files...> LINK <targets...>): an optional module
# beside the core (mpi/, bullet/). It defines the library granular_<name> (granular::<name>) from
# SOURCES, its public headers in the calling folder's include/, linked to granular_core and LINK; and
# installs it in an export set of its own (<export set>.cmake), which the package config loads only
# when the module's dependency is found where granular is used: find_package(granular) works
# without it, and find_package(granular COMPONENTS <name>) requires it.
include(GNUInstallDirs)
function(granular_add_module name export_set)
  cmake_parse_arguments(PARSE_ARGV 2 ARG "" "" "SOURCES;LINK")
  set(target granular_${name})
  add_library(${target} ${ARG_SOURCES})
  add_library(granular::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME ${target})
  target_compile_features(${target} PUBLIC cxx_std_20)
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:include>)
  target_link_libraries(${target} PUBLIC granular_core ${ARG_LINK})
  if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic)
  endif()
  install(TARGETS ${target} EXPORT ${export_set}
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(DIRECTORY include/granular DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  install(EXPORT ${export_set} NAMESPACE granular:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/granular)
endfunction()
