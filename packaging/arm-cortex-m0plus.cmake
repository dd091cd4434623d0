# arm-cortex-m0plus.cmake - CMake toolchain file: Cortex-M0+ (ARMv6-M, no FPU, soft-float ABI)
# with the GNU Arm Embedded toolchain (arm-none-eabi-gcc, newlib).
# The flags are those grip's m0p library is built with (make TARGET=m0p).
#
#   cmake -S fw -B build -DCMAKE_TOOLCHAIN_FILE=<prefix>/share/grip/cmake/arm-cortex-m0plus.cmake \
#         -DCMAKE_PREFIX_PATH=<prefix>
#   find_package(grip CONFIG REQUIRED COMPONENTS fixed)   -> grip::fixed for this CPU
#
# GRIP_ARM_GCC_PREFIX: path and prefix of the compiler (default
# "arm-none-eabi-", found on PATH), e.g. /opt/arm-gnu/bin/arm-none-eabi-.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)

if(NOT DEFINED GRIP_ARM_GCC_PREFIX)
  set(GRIP_ARM_GCC_PREFIX "arm-none-eabi-")
endif()
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES GRIP_ARM_GCC_PREFIX)
set(CMAKE_C_COMPILER "${GRIP_ARM_GCC_PREFIX}gcc")
set(CMAKE_CXX_COMPILER "${GRIP_ARM_GCC_PREFIX}g++")
set(CMAKE_ASM_COMPILER "${GRIP_ARM_GCC_PREFIX}gcc")

# CPU and ABI: compile and link flags (the link step selects newlib's and
# libgcc's multilib for this CPU from them).
set(GRIP_CPU_FLAGS "-mcpu=cortex-m0plus -mthumb -mfloat-abi=soft")
set(CMAKE_C_FLAGS_INIT "${GRIP_CPU_FLAGS}")
set(CMAKE_CXX_FLAGS_INIT "${GRIP_CPU_FLAGS}")
set(CMAKE_ASM_FLAGS_INIT "${GRIP_CPU_FLAGS}")

# A bare-metal compiler cannot link a test program without the board's
# startup code and linker script: let CMake's compiler checks build a
# static library instead.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

# Programs run on the build machine; headers, libraries and packages come
# from the target's prefixes only (CMAKE_PREFIX_PATH, CMAKE_FIND_ROOT_PATH).
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# Which grip library find_package(grip) gives: this CPU's.
set(GRIP_TARGET m0p CACHE STRING "grip library variant: host, m4f or m0p")
