# the bundled jobs whose reports the browser tests check, run by the built camopt from the
# source tree into OUT (one folder per job, made afresh):
#   cmake -DCAMOPT=<camopt> -DOUT=<dir> -DSCREENSHOTS=<dir> -P run_report_jobs.cmake
# Any job that does not exit 0 stops the script with its command and exit code.
foreach(var CAMOPT OUT SCREENSHOTS)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_report_jobs.cmake: -D${var}=... is required")
  endif()
endforeach()
get_filename_component(source "${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)
file(REMOVE_RECURSE "${OUT}" "${SCREENSHOTS}")
file(MAKE_DIRECTORY "${OUT}" "${SCREENSHOTS}")

function(camopt_job)
  execute_process(COMMAND "${CAMOPT}" -q --threads 2 ${ARGN} WORKING_DIRECTORY "${source}" RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    string(REPLACE ";" " " shown "${ARGN}")
    message(FATAL_ERROR "camopt ${shown}: exit ${rc}")
  endif()
endfunction()

# the synthesis of scripts/setup.sh --run-default: the RFF's cam made for the bundled target lift
camopt_job(synthesize designs/targets/rff_intake_lift.csv --design designs/roller_finger_follower.toml
           --out "${OUT}/synthesize")
# the CVVL at 17 control positions (every output)
camopt_job(kinematics designs/cvvl_swing_cam.toml --control 0:16:17 --outputs all --step 0.5
           --out "${OUT}/kinematics-cvvl")
# the RFF optimised for the passenger-car intake set, without --verify (with it the run exits
# 5: the made design fails one of the verification checks; the outputs are written all the same)
camopt_job(optimize designs/roller_finger_follower.toml --constraints constraints/passenger_car_intake.toml
           --points 720 --out "${OUT}/optimize-rff")
# the dynamics: the CVVL rigid over 4 engine speeds, the RFF flexible at 6000 rpm
camopt_job(dynamics designs/cvvl_swing_cam.toml --model rigid --rpm 1000:7000:4 --out "${OUT}/rigid-cvvl")
camopt_job(dynamics designs/roller_finger_follower.toml --model flexible --rpm 6000 --out "${OUT}/flexible-rff")
