# The ctest entry install.consumer (cmake -P): installs a built vknerf tree into a private prefix,
# checks what was installed, then configures, builds and runs tests/consumer/ against that prefix
# only (find_package through CMAKE_PREFIX_PATH, never the build tree). Any failed step fails the test.
#
# Everything it writes is under SCRATCH_DIR (emptied first), plus the build tree's
# install_manifest.txt, which `cmake --install` always writes; no other test installs.

foreach(var VKNERF_BUILD_DIR VKNERF_SOURCE_DIR SCRATCH_DIR GENERATOR CXX_COMPILER LIBRARY_FILE
            INSTALL_LIBDIR INSTALL_BINDIR INSTALL_INCLUDEDIR PROJECT_VERSION)
  if("${${var}}" STREQUAL "")
    message(FATAL_ERROR "RunConsumerTest.cmake: -D${var}=... is required")
  endif()
endforeach()

set(prefix ${SCRATCH_DIR}/prefix)
set(consumer_build ${SCRATCH_DIR}/build)
set(package_dir ${prefix}/${INSTALL_LIBDIR}/cmake/vknerf)
file(REMOVE_RECURSE ${SCRATCH_DIR})
file(MAKE_DIRECTORY ${SCRATCH_DIR})

# The build type of the tree being installed; the consumer is built with the same one.
set(config_args "")
if(NOT "${BUILD_CONFIG}" STREQUAL "")
  set(config_args --config ${BUILD_CONFIG})
endif()

function(run_step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc COMMAND_ECHO STDOUT)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "install.consumer: ${what} failed (exit status: ${rc})")
  endif()
endfunction()

function(require_file path)
  if(NOT EXISTS ${path})
    message(FATAL_ERROR "install.consumer: ${path} was not installed")
  endif()
endfunction()

# 1. Install.
run_step("cmake --install" ${CMAKE_COMMAND} --install ${VKNERF_BUILD_DIR} --prefix ${prefix} ${config_args})

# 2. What must be there: every public header, the library, the package files, the command line.
file(GLOB public_headers RELATIVE ${VKNERF_SOURCE_DIR}/include ${VKNERF_SOURCE_DIR}/include/vknerf/*.h)
list(LENGTH public_headers header_count)
if(header_count EQUAL 0)
  message(FATAL_ERROR "install.consumer: no public headers found under ${VKNERF_SOURCE_DIR}/include/vknerf")
endif()
foreach(header ${public_headers})
  require_file(${prefix}/${INSTALL_INCLUDEDIR}/${header})
endforeach()
require_file(${prefix}/${INSTALL_LIBDIR}/${LIBRARY_FILE})
require_file(${package_dir}/vknerfConfig.cmake)
require_file(${package_dir}/vknerfConfigVersion.cmake)
require_file(${package_dir}/vknerfTargets.cmake)
if(NOT "${CLI_FILE}" STREQUAL "")
  require_file(${prefix}/${INSTALL_BINDIR}/${CLI_FILE})
  # The installed binary runs from its new place (no build-tree paths needed): list the devices.
  run_step("installed ${CLI_FILE} info" ${prefix}/${INSTALL_BINDIR}/${CLI_FILE} info)
endif()

# 3. The version file: this version and an older minor of the same major are accepted, the next
#    major is not (SameMajorVersion), exactly as find_package would ask.
function(check_version requested expected)
  string(REPLACE "." ";" parts ${requested})
  list(GET parts 0 PACKAGE_FIND_VERSION_MAJOR)
  list(GET parts 1 PACKAGE_FIND_VERSION_MINOR)
  set(PACKAGE_FIND_VERSION ${requested})
  set(PACKAGE_FIND_NAME vknerf)
  include(${package_dir}/vknerfConfigVersion.cmake)
  if(NOT PACKAGE_VERSION STREQUAL PROJECT_VERSION)
    message(FATAL_ERROR "install.consumer: the version file says ${PACKAGE_VERSION}, the project is ${PROJECT_VERSION}")
  endif()
  if((expected AND NOT PACKAGE_VERSION_COMPATIBLE) OR (NOT expected AND PACKAGE_VERSION_COMPATIBLE))
    message(FATAL_ERROR "install.consumer: version ${PACKAGE_VERSION} compatible with a request for "
                        "${requested}: ${PACKAGE_VERSION_COMPATIBLE}, expected ${expected}")
  endif()
endfunction()
string(REPLACE "." ";" version_parts ${PROJECT_VERSION})
list(GET version_parts 0 major)
math(EXPR next_major "${major} + 1")
check_version(${PROJECT_VERSION} TRUE)
check_version(${major}.0 TRUE)
check_version(${next_major}.0 FALSE)

# 4. Configure the consumer against the prefix alone, with this build's compiler and build type.
run_step("configuring tests/consumer"
  ${CMAKE_COMMAND} -S ${VKNERF_SOURCE_DIR}/tests/consumer -B ${consumer_build} -G ${GENERATOR}
  -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DCMAKE_BUILD_TYPE=${BUILD_CONFIG}
  -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
  -DVKNERF_REQUIRE_VERSION=${PROJECT_VERSION})
file(STRINGS ${consumer_build}/CMakeCache.txt found_dir REGEX "^vknerf_DIR:")
string(REGEX REPLACE "^vknerf_DIR:[A-Z]+=" "" found_dir "${found_dir}")
file(REAL_PATH "${found_dir}" found_dir)
file(REAL_PATH ${package_dir} expected_dir)
if(NOT found_dir STREQUAL expected_dir)
  message(FATAL_ERROR "install.consumer: the consumer found vknerf in '${found_dir}', not in ${expected_dir}")
endif()

# 5. Build it (one .cpp) and run it; it exits non-zero on a failed check or a validation message.
run_step("building tests/consumer" ${CMAKE_COMMAND} --build ${consumer_build} ${config_args})
file(GLOB_RECURSE consumer_exe LIST_DIRECTORIES false ${consumer_build}/vknerf_consumer ${consumer_build}/vknerf_consumer.exe)
list(LENGTH consumer_exe exe_count)
if(NOT exe_count EQUAL 1)
  message(FATAL_ERROR "install.consumer: expected one vknerf_consumer executable under ${consumer_build}, found '${consumer_exe}'")
endif()
run_step("running vknerf_consumer" ${consumer_exe})
