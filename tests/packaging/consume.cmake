# Configures, builds and runs a small project that uses anima.
#
#   cmake -DPROJECT_DIR=<consumer project> -DWORK_DIR=<scratch dir>
#         [-DINSTALL_FROM=<anima build tree>]  install anima there first and
#                                              find it through CMAKE_PREFIX_PATH
#         [-DANIMA_SOURCE_DIR=<anima sources>] forwarded to the consumer
#         [-DGENERATOR=... -DMAKE_PROGRAM=... -DCXX_COMPILER=... -DCXX_FLAGS=...
#          -DEXE_LINKER_FLAGS=... -DCONFIG=... -DEigen3_DIR=... -Dglm_DIR=...]
#         -P consume.cmake
cmake_minimum_required(VERSION 3.16)

foreach(required PROJECT_DIR WORK_DIR)
  if(NOT ${required})
    message(FATAL_ERROR "consume.cmake: ${required} is not set")
  endif()
endforeach()

# run_step(<description> [IN <dir>] COMMAND <command...>)
function(run_step description)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "IN" "COMMAND")
  if(NOT arg_IN)
    set(arg_IN "${WORK_DIR}")
  endif()
  string(REPLACE ";" " " shown "${arg_COMMAND}")
  message(STATUS "${description}: ${shown}")
  execute_process(COMMAND ${arg_COMMAND} WORKING_DIRECTORY "${arg_IN}" RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "${description} failed (${result})")
  endif()
endfunction()

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

set(config_args "")
set(ctest_config_args "")
if(CONFIG)
  set(config_args --config "${CONFIG}")
  set(ctest_config_args -C "${CONFIG}")
endif()

set(configure_args -S "${PROJECT_DIR}" -B "${WORK_DIR}/build")
if(GENERATOR)
  list(APPEND configure_args -G "${GENERATOR}")
endif()
# Forward only what is set, so the consumer otherwise sees CMake's defaults.
foreach(pair
    MAKE_PROGRAM:CMAKE_MAKE_PROGRAM
    CXX_COMPILER:CMAKE_CXX_COMPILER
    CXX_FLAGS:CMAKE_CXX_FLAGS
    EXE_LINKER_FLAGS:CMAKE_EXE_LINKER_FLAGS
    CONFIG:CMAKE_BUILD_TYPE
    Eigen3_DIR:Eigen3_DIR
    glm_DIR:glm_DIR
    ANIMA_SOURCE_DIR:ANIMA_SOURCE_DIR)
  string(REPLACE ":" ";" pair "${pair}")
  list(GET pair 0 from)
  list(GET pair 1 to)
  if(${from})
    list(APPEND configure_args "-D${to}=${${from}}")
  endif()
endforeach()

if(INSTALL_FROM)
  # Only the library component: installing must not need anything built.
  run_step("Installing anima" COMMAND
    "${CMAKE_COMMAND}" --install "${INSTALL_FROM}" --prefix "${WORK_DIR}/prefix"
    --component anima_dev ${config_args})
  list(APPEND configure_args "-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix")
endif()

run_step("Configuring consumer" COMMAND "${CMAKE_COMMAND}" ${configure_args})
run_step("Building consumer" COMMAND "${CMAKE_COMMAND}" --build "${WORK_DIR}/build" ${config_args})
# The consumer registers its executable with add_test(); ctest finds it
# wherever the generator put it.
run_step("Running consumer" IN "${WORK_DIR}/build" COMMAND
  "${CMAKE_CTEST_COMMAND}" --output-on-failure --no-tests=error ${ctest_config_args})
