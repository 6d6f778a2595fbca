# SPDX-License-Identifier: MIT
# The installed package configuration's per-component needs, read from the targets the build
# declares (docs/architecture.md "Components"), so sonarsynthConfig.cmake cannot disagree with
# them: for each component, the components it links (transitively, PUBLIC and PRIVATE alike: a
# static library's private dependencies are its users' link dependencies) and the third-party
# packages its own targets link.
#
# sonarsynth_package_needs(<output variable> COMPONENTS <c>...) sets <output variable> to CMake
# code that defines _sonarsynth_components, _sonarsynth_needs_<c> and _sonarsynth_packages_<c>
# (the find_dependency() arguments, one package per "|"-separated entry).

# Imported target -> find_dependency() arguments. A target missing here is an error, so a new
# third-party library cannot reach the installed package without its find_dependency line.
set(_sonarsynth_package_of_Eigen3::Eigen "Eigen3 3.3 NO_MODULE")
set(_sonarsynth_package_of_Threads::Threads "Threads")
set(_sonarsynth_package_of_GeographicLib::GeographicLib "GeographicLib")
set(_sonarsynth_package_of_hwy::hwy "hwy")
set(_sonarsynth_package_of_GDAL::GDAL "GDAL CONFIG")
set(_sonarsynth_package_of_PNG::PNG "PNG")
set(_sonarsynth_package_of_ISAL::ISAL "ISAL")
set(_sonarsynth_package_of_yaml-cpp "yaml-cpp")
set(_sonarsynth_package_of_OpenSSL::Crypto "OpenSSL COMPONENTS Crypto")
set(_sonarsynth_package_of_assimp::assimp "assimp CONFIG")
set(_sonarsynth_package_of_zstd::libzstd_shared "zstd CONFIG")
set(_sonarsynth_package_of_ZLIB::ZLIB "ZLIB")

# The direct link items of target <t> that matter to an installed user: generator expressions
# that exist only in the build tree ($<BUILD_INTERFACE:...>) are dropped.
function(_sonarsynth_link_items t out)
  get_target_property(items ${t} LINK_LIBRARIES)
  if(NOT items)
    set(items "")
  endif()
  set(kept "")
  foreach(item IN LISTS items)
    if(item MATCHES "^\\$<BUILD_INTERFACE:")
      continue()
    endif()
    list(APPEND kept ${item})
  endforeach()
  set(${out} ${kept} PARENT_SCOPE)
endfunction()

function(sonarsynth_package_needs out)
  cmake_parse_arguments(ARG "" "" "COMPONENTS" ${ARGN})
  set(code "set(_sonarsynth_components ${ARG_COMPONENTS})\n")
  foreach(c IN LISTS ARG_COMPONENTS)
    # Components: breadth-first closure over sonarsynth_<x> link items.
    set(needs "")
    set(queue sonarsynth_${c})
    while(queue)
      list(POP_FRONT queue t)
      _sonarsynth_link_items(${t} items)
      foreach(item IN LISTS items)
        if(item MATCHES "^sonarsynth_(.+)$" AND CMAKE_MATCH_1 IN_LIST ARG_COMPONENTS)
          if(NOT CMAKE_MATCH_1 IN_LIST needs)
            list(APPEND needs ${CMAKE_MATCH_1})
            list(APPEND queue ${item})
          endif()
        endif()
      endforeach()
    endwhile()
    # Keep the components' declared (dependency) order.
    set(ordered "")
    foreach(d IN LISTS ARG_COMPONENTS)
      if(d IN_LIST needs)
        list(APPEND ordered ${d})
      endif()
    endforeach()
    # Third-party packages of this component's own target.
    _sonarsynth_link_items(sonarsynth_${c} items)
    set(packages "")
    foreach(item IN LISTS items)
      if(item MATCHES "^sonarsynth_" OR item MATCHES "^\\$<")
        continue()
      endif()
      if(NOT DEFINED _sonarsynth_package_of_${item})
        message(FATAL_ERROR "sonarsynth_${c} links ${item}: add its find_dependency() arguments "
                            "to cmake/SonarsynthPackageNeeds.cmake")
      endif()
      list(APPEND packages "${_sonarsynth_package_of_${item}}")
    endforeach()
    string(REPLACE ";" "|" packages "${packages}")
    string(APPEND code "set(_sonarsynth_needs_${c} \"${ordered}\")\n"
                       "set(_sonarsynth_packages_${c} \"${packages}\")\n")
  endforeach()
  set(${out} "${code}" PARENT_SCOPE)
endfunction()
