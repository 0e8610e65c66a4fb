import os

from conan import ConanFile
from conan.tools.build import check_min_cppstd
from conan.tools.files import copy


class AnimaConan(ConanFile):
    name = "anima"
    version = "0.1.0"
    license = "MIT"
    description = "Header-only C++17 character animation maths: rotations, skeletons, BVH motion capture."
    topics = ("animation", "quaternion", "skeleton", "bvh", "header-only")
    package_type = "header-library"
    settings = "os", "arch", "compiler", "build_type"
    exports_sources = "include/*", "CMakeLists.txt", "cmake/*", "LICENSE"
    no_copy_source = True

    def requirements(self):
        # anima's public headers include Eigen and GLM, so consumers need them too.
        self.requires("eigen/3.4.0", transitive_headers=True)
        self.requires("glm/cci.20230113", transitive_headers=True)

    def validate(self):
        if self.settings.get_safe("compiler.cppstd"):
            check_min_cppstd(self, 17)

    def package_id(self):
        self.info.clear()

    def package(self):
        copy(self, "LICENSE", self.source_folder, os.path.join(self.package_folder, "licenses"))
        copy(self, "*", os.path.join(self.source_folder, "include"),
             os.path.join(self.package_folder, "include"))

    def package_info(self):
        self.cpp_info.set_property("cmake_file_name", "anima")
        self.cpp_info.set_property("cmake_target_name", "anima::anima")
        self.cpp_info.bindirs = []
        self.cpp_info.libdirs = []
