# Installs the configured build tree BUILD_DIR to a fresh prefix under WORK_DIR, configures the
# consumer in SOURCE_DIR/examples/cpp against it in one fresh configure, builds it and runs it:
# find_package(cutdyn) must give a usable cutdyn::cutdyn target.
foreach(var BUILD_DIR SOURCE_DIR WORK_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "consumer_test: ${var} not set")
  endif()
endforeach()
file(REMOVE_RECURSE "${WORK_DIR}")
set(prefix "${WORK_DIR}/prefix")
set(consumer "${WORK_DIR}/consumer")
function(run)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "consumer_test: `${ARGV}` failed (${rc}):\n${out}\n${err}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()
run(${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${prefix}")
run(${CMAKE_COMMAND} -S "${SOURCE_DIR}/examples/cpp" -B "${consumer}" -G Ninja
    -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=${prefix}")
run(${CMAKE_COMMAND} --build "${consumer}")
run("${consumer}/milling_lobes")
# The Insperger–Stépán slotting limit at 5000 rpm is 0.048 mm (the lobes' lowest at 5000 rpm).
string(REGEX MATCH "\n5000\\.0,([0-9.]+)," line "${last_output}")
if(NOT CMAKE_MATCH_1 OR CMAKE_MATCH_1 LESS 0.045 OR CMAKE_MATCH_1 GREATER 0.051)
  message(FATAL_ERROR "consumer_test: unexpected output:\n${last_output}")
endif()
# One fresh configure of cutdyn itself must export the include directory (GNUInstallDirs was
# once included after CMAKE_INSTALL_INCLUDEDIR was used: empty on a first configure).
run(${CMAKE_COMMAND} -S "${SOURCE_DIR}" -B "${WORK_DIR}/fresh" -G Ninja
    -DCUTDYN_BUILD_TESTS=OFF -DCUTDYN_BUILD_BENCHMARKS=OFF)
file(GLOB_RECURSE exports "${WORK_DIR}/fresh/CMakeFiles/Export/*/cutdynTargets.cmake")
if(NOT exports)
  message(FATAL_ERROR "consumer_test: no exported cutdynTargets.cmake after a fresh configure")
endif()
list(GET exports 0 export_file)
file(READ "${export_file}" export_text)
if(NOT export_text MATCHES "INTERFACE_INCLUDE_DIRECTORIES \"\\\${_IMPORT_PREFIX}/include\"")
  message(FATAL_ERROR "consumer_test: a fresh configure exports no include directory (${export_file})")
endif()
# The jobs: the `check` job on a built-in example through cutdyn::app (the Insperger–Stépán
# slot at 5000 rpm and 0.04 mm: stable, below the 0.048 mm lobe).
run("${consumer}/check_cut")
if(NOT last_output MATCHES "\nstable at 5000 rpm and 0\\.040 mm: critical depth 0\\.04[5-9]")
  message(FATAL_ERROR "consumer_test: unexpected output of check_cut:\n${last_output}")
endif()
# The monitor's estimate job, fed a log in chunks (300 samples, the mean force 2500 N).
run("${consumer}/monitor_estimate")
if(NOT last_output MATCHES "(^|\n)300,2500\\.0,")
  message(FATAL_ERROR "consumer_test: unexpected output of monitor_estimate:\n${last_output}")
endif()
# The Python module, when the build made one: installed into the prefix's Python directory,
# importable from there, giving the lobes (docs/python.md).
file(GLOB built_module "${BUILD_DIR}/python/cutdyn/_cutdyn*")
if(built_module)
  file(GLOB_RECURSE installed_module "${prefix}/lib*/python3*/dist-packages/cutdyn/_cutdyn*")
  if(NOT installed_module)
    message(FATAL_ERROR "consumer_test: the Python module was built but not installed")
  endif()
  list(GET installed_module 0 module_file)
  get_filename_component(package_dir "${module_file}" DIRECTORY)
  get_filename_component(site_dir "${package_dir}" DIRECTORY)
  find_program(python NAMES python3 PATHS /usr/bin NO_DEFAULT_PATH)
  # (No semicolons in the script: run() passes its arguments on as a list.)
  run(${CMAKE_COMMAND} -E env "PYTHONPATH=${site_dir}" ${python} -c
      "import cutdyn\nprint(cutdyn.__file__)\nprint(cutdyn.lobes(cutdyn.example('milling-insperger')).lowest)")
  string(FIND "${last_output}" "${site_dir}/cutdyn/__init__.py\n" at)
  if(NOT at EQUAL 0 OR NOT last_output MATCHES "'critical_depth_mm': 0\\.04[5-9]")
    message(FATAL_ERROR "consumer_test: unexpected output of the installed Python module:\n${last_output}")
  endif()
endif()
# Internal headers (detail/) are not installed.
file(GLOB_RECURSE internal "${prefix}/include/cutdyn/*/detail/*")
if(internal)
  message(FATAL_ERROR "consumer_test: internal headers were installed: ${internal}")
endif()
message(STATUS "consumer_test: the installed cutdyn builds and runs a consumer")
