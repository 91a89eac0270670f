# Cross-compiling svetlo for ARM64 (aarch64) Linux with Debian's g++-aarch64-linux-gnu and the
# arm64 libraries installed beside the machine's own (multiarch): `make test-arm64`, after
# `scripts/setup arm64` (docs/kernels.md). The tests run under qemu-user.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)

# Libraries and packages for the target only; programs (python3, qemu) from the machine.
set(CMAKE_FIND_ROOT_PATH /usr /opt/svetlo-arm64/openexr/usr)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# OpenEXR's arm64 development files are unpacked apart by scripts/setup arm64.
set(OpenEXR_DIR /opt/svetlo-arm64/openexr/usr/lib/aarch64-linux-gnu/cmake/OpenEXR)

# The tests' programs run under qemu-user; the arm64 C library lives in /lib (multiarch).
find_program(QEMU_AARCH64 qemu-aarch64 REQUIRED)
set(CMAKE_CROSSCOMPILING_EMULATOR ${QEMU_AARCH64})

# pkg-config reads the arm64 libraries' files, not the machine's.
set(ENV{PKG_CONFIG_LIBDIR} /usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig)
# MPI's compiler wrappers are the machine's: the cross build runs as one process.
set(CMAKE_DISABLE_FIND_PACKAGE_MPI ON)
