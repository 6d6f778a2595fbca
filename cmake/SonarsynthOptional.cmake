# SPDX-License-Identifier: MIT
# sonarsynth_optional(NAME DOC FOUND_VAR FIND_CODE MISSING): one optional dependency.
# Declares the cache choice SONARSYNTH_WITH_<NAME> (AUTO, ON, OFF; DOC says what it builds) and sets
# SONARSYNTH_HAVE_<NAME>. Unless OFF, FIND_CODE (the find commands) runs and FOUND_VAR tells whether
# it found the package; ON without it is a configure error ending with MISSING (what to install).
# A macro, so that the variables the find commands set stay in the caller's scope.
macro(sonarsynth_optional name doc found_var find_code missing)
  set(SONARSYNTH_WITH_${name} AUTO CACHE STRING "${doc}: AUTO, ON, OFF")
  set_property(CACHE SONARSYNTH_WITH_${name} PROPERTY STRINGS AUTO ON OFF)
  set(SONARSYNTH_HAVE_${name} OFF)
  if(SONARSYNTH_WITH_${name} STREQUAL "AUTO" OR SONARSYNTH_WITH_${name})
    cmake_language(EVAL CODE "${find_code}")
    if(${found_var})
      set(SONARSYNTH_HAVE_${name} ON)
    elseif(NOT SONARSYNTH_WITH_${name} STREQUAL "AUTO")
      message(FATAL_ERROR "SONARSYNTH_WITH_${name}=${SONARSYNTH_WITH_${name}} but ${missing}")
    endif()
  endif()
  message(STATUS "${doc}: ${SONARSYNTH_HAVE_${name}}")
endmacro()
