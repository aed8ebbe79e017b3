# The layering rule of src/, checked (ctest -L layers; cmake/modules.cmake declares the rule):
#   cmake -DSOURCE_DIR=<tree> -DMODULE_DEPS=<build>/generated/module_deps.cmake \
#         -P cmake/check_layers.cmake
# Fails, one line per finding, when
#   - a file of module M includes "N/..." where N is a directory of src/ that is not M and not
#     among M's declared dependencies (or is no declared module at all),
#   - the modules' includes, or the declared dependencies, form a cycle.
# "kernels/..." and "shaders/..." (the source tree's root) are not modules; src/main.cpp, the
# entry point above every module, is not checked.
cmake_minimum_required(VERSION 3.20)
if(NOT SOURCE_DIR OR NOT MODULE_DEPS)
  message(FATAL_ERROR "usage: cmake -DSOURCE_DIR=... -DMODULE_DEPS=... -P check_layers.cmake")
endif()
include(${MODULE_DEPS})  # TILESHADE_MODULES, TILESHADE_DEPS_<module>

set(failures 0)
macro(fail line)
  message("check_layers: ${line}")
  math(EXPR failures "${failures} + 1")
endmacro()

file(GLOB src_entries RELATIVE ${SOURCE_DIR}/src ${SOURCE_DIR}/src/*)
set(src_dirs "")
foreach(entry IN LISTS src_entries)
  if(IS_DIRECTORY ${SOURCE_DIR}/src/${entry})
    list(APPEND src_dirs ${entry})
    if(NOT entry IN_LIST TILESHADE_MODULES)
      fail("src/${entry}/: no tileshade_module(${entry} ...) in cmake/modules.cmake")
    endif()
  endif()
endforeach()

# Every include of a src/ directory, checked against the declared dependencies; the edges found
# are kept (uses_<M>) for the cycle check below.
foreach(module IN LISTS TILESHADE_MODULES)
  set(uses_${module} "")
endforeach()
foreach(module IN LISTS src_dirs)
  file(GLOB_RECURSE files RELATIVE ${SOURCE_DIR} ${SOURCE_DIR}/src/${module}/*.h
       ${SOURCE_DIR}/src/${module}/*.cpp)
  list(SORT files)
  foreach(file IN LISTS files)
    file(STRINGS ${SOURCE_DIR}/${file} includes REGEX "^[ \t]*#[ \t]*include[ \t]*\"[^\"/]+/")
    foreach(line IN LISTS includes)
      string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*\"([^\"]+)\".*$" "\\1" path "${line}")
      string(REGEX REPLACE "/.*$" "" target "${path}")
      if(target STREQUAL module OR NOT target IN_LIST src_dirs)
        continue()  # its own header, or kernels/ or shaders/
      endif()
      if(NOT module IN_LIST TILESHADE_MODULES)
        continue()  # reported above
      endif()
      if(NOT target IN_LIST TILESHADE_DEPS_${module})
        string(REPLACE ";" " " declared "${TILESHADE_DEPS_${module}}")
        fail("${file} includes \"${path}\", but ${module} depends only on: ${declared} (cmake/modules.cmake)")
      endif()
      if(NOT target IN_LIST uses_${module})
        list(APPEND uses_${module} ${target})
      endif()
    endforeach()
  endforeach()
endforeach()

# Depth-first search for a cycle in the graph <prefix>_<module>; reports the first one found.
function(find_cycle prefix what)
  foreach(module IN LISTS TILESHADE_MODULES)
    set(state_${module} 0)  # 0 unvisited, 1 on the current path, 2 done
  endforeach()
  foreach(root IN LISTS TILESHADE_MODULES)
    if(NOT state_${root} EQUAL 0)
      continue()
    endif()
    # An explicit stack of modules and the index of their next edge (CMake has no recursion
    # depth to speak of, and no local variables per call level).
    set(stack ${root})
    set(next_${root} 0)
    set(state_${root} 1)
    while(stack)
      list(GET stack -1 top)
      list(LENGTH ${prefix}_${top} edges)
      if(next_${top} LESS edges)
        list(GET ${prefix}_${top} ${next_${top}} to)
        math(EXPR next_${top} "${next_${top}} + 1")
        if(NOT DEFINED state_${to})
          continue()  # not a module (reported above)
        endif()
        if(state_${to} EQUAL 1)
          list(FIND stack ${to} at)
          list(SUBLIST stack ${at} -1 cycle)
          list(APPEND cycle ${to})
          string(REPLACE ";" " -> " cycle "${cycle}")
          set(cycle_found "${what} form a cycle: ${cycle}" PARENT_SCOPE)
          return()
        endif()
        if(state_${to} EQUAL 0)
          set(state_${to} 1)
          set(next_${to} 0)
          list(APPEND stack ${to})
        endif()
      else()
        set(state_${top} 2)
        list(POP_BACK stack)
      endif()
    endwhile()
  endforeach()
  set(cycle_found "" PARENT_SCOPE)
endfunction()

find_cycle(uses "the modules' includes")
if(cycle_found)
  fail("${cycle_found}")
endif()
find_cycle(TILESHADE_DEPS "the declared dependencies (cmake/modules.cmake)")
if(cycle_found)
  fail("${cycle_found}")
endif()

if(failures GREATER 0)
  message(FATAL_ERROR "check_layers: ${failures} finding(s)")
endif()
list(LENGTH TILESHADE_MODULES count)
message("check_layers: ${count} modules, every include among the declared dependencies, no cycle")
