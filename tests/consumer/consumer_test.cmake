# SPDX-License-Identifier: MIT
# consumer_test.cmake - the `consumer_package` ctest (run as cmake -P; see CMakeLists.txt here).
#
#  1. cmake --install the build into WORK_DIR/prefix (inside the build tree);
#  2. check what was installed, and that libddof.so exports ddof_* symbols only, all of them;
#  3. configure and build tests/consumer/project against that prefix with find_package(ddof),
#     run its shared and its static executable;
#  4. build project/main.c once more from `pkg-config --cflags --libs ddof` and run it.
# Every file it writes is under WORK_DIR; it never needs the network.
cmake_minimum_required(VERSION 3.16)

foreach(var BUILD_DIR WORK_DIR PROJECT_DIR VERSION LIBDIR INCLUDEDIR GENERATOR C_COMPILER)
  if("${${var}}" STREQUAL "")
    message(FATAL_ERROR "consumer_test.cmake needs -D${var}=...")
  endif()
endforeach()

set(prefix "${WORK_DIR}/prefix")
set(libdir "${prefix}/${LIBDIR}")
string(REGEX MATCH "^([0-9]+)\\.([0-9]+)" major_minor "${VERSION}")
set(major ${CMAKE_MATCH_1})
set(minor ${CMAKE_MATCH_2})
set(config_args "")
if(CONFIG)
  set(config_args --config "${CONFIG}")
endif()
set(sanitize_flags "")
if(SANITIZE)
  set(sanitize_flags -fsanitize=address,undefined -fno-omit-frame-pointer)
endif()

# Nothing in the environment may send the install elsewhere or answer a look-up from outside.
foreach(var DESTDIR ddof_DIR ddof_ROOT CMAKE_PREFIX_PATH PKG_CONFIG_SYSROOT_DIR)
  unset(ENV{${var}})
endforeach()

# fail(<text>...): the pieces are joined without separators.
function(fail)
  string(CONCAT text ${ARGV})
  message(FATAL_ERROR "consumer_package: ${text}")
endfunction()

# step(<what> <command...>): runs the command; fails with its output unless it exits with 0.
# Sets step_output (stdout + stderr) in the caller.
function(step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT "${rc}" STREQUAL "0")
    list(JOIN ARGN " " command_line)
    fail("${what} failed (${rc}):\n  ${command_line}\n${out}")
  endif()
  message(STATUS "ok: ${what}")
  string(STRIP "${out}" out)
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

find_program(LDD_EXECUTABLE ldd)
# check_loads(<exe> <expect: DDOF_FROM_PREFIX | NO_DDOF>): what the dynamic loader picks.
function(check_loads exe expect)
  if(NOT LDD_EXECUTABLE)
    return()
  endif()
  execute_process(COMMAND ${LDD_EXECUTABLE} ${exe} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE out)
  if(NOT "${rc}" STREQUAL "0")
    return() # e.g. a sanitizer runtime ldd cannot trace; running it is the real test
  endif()
  string(REGEX MATCH "libddof[^ \t\n]* => ([^ \t\n]+)" hit "${out}")
  if(expect STREQUAL "NO_DDOF")
    if(out MATCHES "libddof")
      fail("${exe} is linked statically but still needs a shared libddof:\n${out}")
    endif()
    return()
  endif()
  if(NOT hit)
    fail("${exe} does not load libddof:\n${out}")
  endif()
  get_filename_component(loaded "${CMAKE_MATCH_1}" REALPATH)
  get_filename_component(loaded_dir "${loaded}" DIRECTORY)
  get_filename_component(want_dir "${libdir}" REALPATH)
  if(NOT loaded_dir STREQUAL want_dir)
    fail("${exe} loads ${loaded}, not the library installed in ${want_dir}")
  endif()
endfunction()

# ---------------------------------------------------------------------------------------------
# 1. Install.
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
step("install into ${prefix}" "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${prefix}"
     ${config_args})

# 2. What was installed.
set(shared_lib "${libdir}/libddof.so")
foreach(file "${prefix}/${INCLUDEDIR}/ddof.h" "${shared_lib}" "${libdir}/libddof.a"
             "${libdir}/cmake/ddof/ddofConfig.cmake" "${libdir}/cmake/ddof/ddofConfigVersion.cmake"
             "${libdir}/cmake/ddof/ddofTargets.cmake" "${libdir}/pkgconfig/ddof.pc")
  if(NOT EXISTS "${file}")
    fail("the install did not create ${file}")
  endif()
endforeach()
file(GLOB_RECURSE headers RELATIVE "${prefix}" "${prefix}/*.h")
foreach(header IN LISTS headers)
  get_filename_component(name "${header}" NAME)
  if(NOT name MATCHES "^ddof")
    fail("an internal header was installed: ${header}")
  endif()
endforeach()
message(STATUS "ok: installed files")

# The soname names the ABI's first release (libddof/CMakeLists.txt), not this version.
find_program(OBJDUMP NAMES objdump)
if(OBJDUMP)
  step("objdump -p libddof.so" "${OBJDUMP}" -p "${shared_lib}")
  if(NOT step_output MATCHES "SONAME +libddof\\.so\\.0\\.5(\n|$)")
    fail("libddof.so's soname is not libddof.so.0.5:\n${step_output}")
  endif()
  message(STATUS "ok: soname libddof.so.0.5")
endif()

# Exported symbols: only ddof_*, and every DDOF_API function of the header.
if(NOT NM)
  find_program(NM NAMES nm)
endif()
if(NOT NM)
  fail("nm not found: cannot check the exported symbols")
endif()
step("nm -D --defined-only libddof.so" "${NM}" -D --defined-only "${shared_lib}")
string(REPLACE "\n" ";" nm_lines "${step_output}")
set(exported "")
set(foreign "")
foreach(line IN LISTS nm_lines)
  if(NOT line MATCHES "^[0-9a-fA-F]* *([A-Za-z]) (.+)$")
    continue()
  endif()
  set(type "${CMAKE_MATCH_1}")
  set(name "${CMAKE_MATCH_2}")
  # Global symbols: upper-case types, 'u' (unique global) and 'i' (ifunc). 'A' marks version
  # nodes, not code or data. _init/_fini are the ELF constructors some linkers export.
  if(NOT type MATCHES "^[B-TV-Zui]$" OR name MATCHES "^_(init|fini)$")
    continue()
  endif()
  if(name MATCHES "^ddof_")
    list(APPEND exported "${name}")
  else()
    list(APPEND foreign "${type} ${name}")
  endif()
endforeach()
if(foreign)
  list(JOIN foreign "\n  " foreign_text)
  fail("libddof.so exports symbols outside the ddof_ namespace:\n  ${foreign_text}")
endif()
file(READ "${prefix}/${INCLUDEDIR}/ddof.h" header_text)
string(REGEX MATCHALL "DDOF_API [^(\n]*[ *]ddof_[a-z0-9_]+\\(" declarations "${header_text}")
set(missing "")
foreach(declaration IN LISTS declarations)
  string(REGEX MATCH "(ddof_[a-z0-9_]+)\\($" unused "${declaration}")
  if(NOT "${CMAKE_MATCH_1}" IN_LIST exported)
    list(APPEND missing "${CMAKE_MATCH_1}")
  endif()
endforeach()
list(LENGTH declarations declared_count)
list(LENGTH exported exported_count)
if(declared_count EQUAL 0)
  fail("found no DDOF_API function in the installed ddof.h")
endif()
if(missing)
  list(JOIN missing ", " missing)
  fail("ddof.h declares functions that libddof.so does not export: ${missing}")
endif()
message(STATUS "ok: libddof.so exports ${exported_count} symbols, all ddof_*; "
               "the ${declared_count} functions of ddof.h are among them")

# ---------------------------------------------------------------------------------------------
# 3. An outside CMake project: find_package(ddof) from the prefix, shared and static.
set(cmake_build "${WORK_DIR}/cmake-build")
set(configure_args -S "${PROJECT_DIR}" -G "${GENERATOR}"
    "-DCMAKE_C_COMPILER=${C_COMPILER}"
    "-DCMAKE_PREFIX_PATH=${prefix}"
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
    -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF
    -DCMAKE_EXPORT_NO_PACKAGE_REGISTRY=ON)
if(MAKE_PROGRAM)
  list(APPEND configure_args "-DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM}")
endif()
if(CONFIG)
  list(APPEND configure_args "-DCMAKE_BUILD_TYPE=${CONFIG}")
endif()
if(sanitize_flags)
  list(JOIN sanitize_flags " " flags)
  list(APPEND configure_args "-DCMAKE_C_FLAGS=${flags}" "-DCMAKE_EXE_LINKER_FLAGS=${flags}")
endif()

# The version check (SameMajorVersion): a newer minor than the one installed is refused, an
# older one of the same ABI (from 0.5) is served.
math(EXPR other_minor "${minor} + 1")
execute_process(COMMAND "${CMAKE_COMMAND}" ${configure_args} -B "${WORK_DIR}/cmake-wrong-version"
                        "-DDDOF_REQUIRED_VERSION=${major}.${other_minor}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if("${rc}" STREQUAL "0")
  fail("find_package(ddof ${major}.${other_minor}) accepted the installed ${VERSION}")
endif()
message(STATUS "ok: find_package(ddof ${major}.${other_minor}) refuses ${VERSION}")
if(major EQUAL 0 AND minor GREATER 5)
  execute_process(COMMAND "${CMAKE_COMMAND}" ${configure_args} -B "${WORK_DIR}/cmake-older-version"
                          "-DDDOF_REQUIRED_VERSION=0.5"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT "${rc}" STREQUAL "0")
    fail("find_package(ddof 0.5) refused the installed ${VERSION}:\n${out}")
  endif()
  message(STATUS "ok: find_package(ddof 0.5) accepts ${VERSION}")
endif()

step("configure the consumer project" "${CMAKE_COMMAND}" ${configure_args} -B "${cmake_build}"
     "-DDDOF_REQUIRED_VERSION=${major}.${minor}")
file(STRINGS "${cmake_build}/CMakeCache.txt" ddof_dir_line REGEX "^ddof_DIR:")
string(REGEX REPLACE "^ddof_DIR:[A-Z]+=" "" found_dir "${ddof_dir_line}")
get_filename_component(found_dir "${found_dir}" REALPATH)
get_filename_component(want_dir "${libdir}/cmake/ddof" REALPATH)
if(NOT found_dir STREQUAL want_dir)
  fail("find_package(ddof) found ${found_dir}, not the package installed in ${want_dir}")
endif()
step("build the consumer project" "${CMAKE_COMMAND}" --build "${cmake_build}" ${config_args})

foreach(kind shared static)
  set(exe "${cmake_build}/bin/consumer_${kind}")
  step("run consumer_${kind} (find_package)" "${exe}")
  message(STATUS "   ${step_output}")
endforeach()
check_loads("${cmake_build}/bin/consumer_shared" DDOF_FROM_PREFIX)
check_loads("${cmake_build}/bin/consumer_static" NO_DDOF)

# ---------------------------------------------------------------------------------------------
# 4. pkg-config: only the installed ddof.pc may answer.
if(NOT PKG_CONFIG)
  fail("pkg-config not found: cannot check ddof.pc")
endif()
set(ENV{PKG_CONFIG_PATH} "${libdir}/pkgconfig")
set(ENV{PKG_CONFIG_LIBDIR} "${libdir}/pkgconfig")
step("pkg-config --modversion ddof" "${PKG_CONFIG}" --modversion ddof)
string(STRIP "${step_output}" pc_version)
if(NOT pc_version STREQUAL VERSION)
  fail("ddof.pc says version ${pc_version}, the build is ${VERSION}")
endif()
step("pkg-config --variable=includedir ddof" "${PKG_CONFIG}" --variable=includedir ddof)
string(STRIP "${step_output}" pc_includedir)
get_filename_component(pc_real "${pc_includedir}" REALPATH)
get_filename_component(want_real "${prefix}/${INCLUDEDIR}" REALPATH)
if(NOT pc_real STREQUAL want_real)
  fail("ddof.pc installed into ${prefix} says includedir=${pc_includedir}: the .pc file keeps "
       "the configure-time CMAKE_INSTALL_PREFIX, so it is wrong for any other prefix "
       "(cmake --install --prefix, a staged or moved install). Write its prefix relative to "
       "\${pcfiledir}.")
endif()
step("pkg-config --cflags --libs ddof" "${PKG_CONFIG}" --cflags --libs ddof)
string(STRIP "${step_output}" pc_flags)
separate_arguments(pc_flags UNIX_COMMAND "${pc_flags}")
set(pc_exe "${WORK_DIR}/consumer_pkgconfig")
step("compile main.c with pkg-config flags" "${C_COMPILER}" -std=c11 -Wall -Wextra -Wpedantic
     -Werror ${sanitize_flags} "${PROJECT_DIR}/main.c" ${pc_flags} -o "${pc_exe}")
if("$ENV{LD_LIBRARY_PATH}" STREQUAL "")
  set(ENV{LD_LIBRARY_PATH} "${libdir}")
else()
  set(ENV{LD_LIBRARY_PATH} "${libdir}:$ENV{LD_LIBRARY_PATH}")
endif()
step("run consumer_pkgconfig (pkg-config, LD_LIBRARY_PATH)" "${pc_exe}")
message(STATUS "   ${step_output}")
check_loads("${pc_exe}" DDOF_FROM_PREFIX)

message(STATUS "consumer_package: all checks passed")
