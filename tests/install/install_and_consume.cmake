# cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DGENERATOR=... -DCXX_COMPILER=...
#   -DPARTS=a,b,... -P install_and_consume.cmake
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "failed (${code}): ${ARGN}\n${out}\n${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()

run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(f bin/skin include/skin/model/skin_model.hpp include/skin/batch/batch.hpp
    lib/libskin_model.a lib/cmake/SpectralSkin/SpectralSkinConfig.cmake
    lib/cmake/SpectralSkin/SpectralSkinTargets.cmake share/spectral_skin/data/d65.csv)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "not installed: ${f}")
  endif()
endforeach()
# Headers of the libraries only: none of the application's.
if(EXISTS ${prefix}/include/common.hpp OR EXISTS ${prefix}/include/skin/app)
  message(FATAL_ERROR "application headers installed")
endif()

run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/consumer -B ${WORK_DIR}/consumer -G ${GENERATOR}
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_CXX_COMPILER=${CXX_COMPILER})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/consumer)
run(${WORK_DIR}/consumer/skin_consumer)
set(consumer "${out}")
# The installed library computes what the command does.
run(${prefix}/bin/skin color --preset caucasian --format json)
string(REGEX MATCH "\"hex\": \"(#[0-9a-f]+)\"" hex "${out}")
if(NOT consumer MATCHES "^caucasian ${CMAKE_MATCH_1}\n")
  message(FATAL_ERROR "consumer printed:\n${consumer}\nskin color gives ${CMAKE_MATCH_1}")
endif()
string(REGEX MATCHALL "R_d\\(550 nm\\) [0-9.]+" rd "${consumer}")
list(LENGTH rd n)
if(NOT n EQUAL 5)
  message(FATAL_ERROR "consumer printed:\n${consumer}")
endif()
message(STATUS "consumer:\n${consumer}")

# Every exported target in one project (tests/install/all_targets): configures, builds, runs.
string(REPLACE "," ";" parts "${PARTS}")
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/install/all_targets -B ${WORK_DIR}/all_targets -G ${GENERATOR}
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
  -DEXPECTED_PARTS=${PARTS})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/all_targets)
run(${WORK_DIR}/all_targets/all_targets)
list(REMOVE_ITEM parts util physics transport color model)
string(REPLACE ";" " " expected_line "ok util physics transport color model ${parts}")
string(STRIP "${expected_line}" expected_line)
if(NOT out STREQUAL "${expected_line}\n")
  message(FATAL_ERROR "all_targets printed '${out}', expected '${expected_line}'")
endif()
message(STATUS "all_targets: ${out}")
