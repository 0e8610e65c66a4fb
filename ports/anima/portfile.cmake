# Overlay port building anima from this checkout:
#   vcpkg install anima --overlay-ports=<checkout>/ports
# Header-only: a single release configuration is enough.
set(VCPKG_BUILD_TYPE release)

set(SOURCE_PATH "${CMAKE_CURRENT_LIST_DIR}/../..")

vcpkg_cmake_configure(
    SOURCE_PATH "${SOURCE_PATH}"
    OPTIONS
        -DANIMA_BUILD_TESTS=OFF
        -DANIMA_BUILD_EXAMPLES=OFF
        -DANIMA_BUILD_BENCHMARKS=OFF
)
vcpkg_cmake_install()
# The package config is installed to share/cmake/anima; vcpkg wants share/anima.
vcpkg_cmake_config_fixup(CONFIG_PATH share/cmake/anima)

file(REMOVE_RECURSE "${CURRENT_PACKAGES_DIR}/debug")
# vcpkg keeps the licence as share/anima/copyright instead of share/doc/anima.
file(REMOVE_RECURSE "${CURRENT_PACKAGES_DIR}/share/doc")
vcpkg_install_copyright(FILE_LIST "${SOURCE_PATH}/LICENSE")
