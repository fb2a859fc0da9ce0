# What `cmake --install` and the Debian package (cpack) put on a machine: the meshtour program and
# its documentation, nothing of the tests or benchmarks. The program reads nothing from the source
# tree at run time (the default scene is compiled in; the caption font is found through
# fontconfig), so the documentation is all that goes beside it. Every destination is relative to
# the prefix (GNUInstallDirs), so the tree can be installed, or a package extracted, anywhere.
include(GNUInstallDirs)

install(TARGETS meshtour RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# The README with docs/ and scenes/ beside it, as in the repository, so that its links resolve.
install(FILES README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/docs)
install(FILES scenes/README.md scenes/default.json DESTINATION ${CMAKE_INSTALL_DOCDIR}/scenes)

# The Debian package: `cpack` in a build folder writes meshtour_<version>_<arch>.deb there.
set(MESHTOUR_PACKAGE_MAINTAINER "meshtour maintainers <maintainers@users.noreply.h-seed-bf62b030.example>"
    CACHE STRING "Maintainer field of the Debian package")
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME meshtour)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "${MESHTOUR_PACKAGE_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${MESHTOUR_PACKAGE_MAINTAINER}")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "offline renderer of camera tours around 3D meshes")
# The summary above is the Description's first line; this is the rest.
set(CPACK_DEBIAN_PACKAGE_DESCRIPTION "meshtour turns a triangle mesh (OBJ, PLY, OFF, STL, glTF or GLB) into a tour video with no human
in the loop: the camera path is computed from the mesh's geometry (toroidal patches or a feature
orbit) or is a turntable, the frames are ray traced on the CPU with Embree, and FFmpeg's
libraries encode them (H.264, VP9, ProRes, FFV1 or GIF). Without input it renders a built-in scene.")
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
# The shared libraries the program links (Embree, TBB, OpenImageIO, libav*, FreeType, fontconfig,
# Qhull, Draco, ...) become dependencies through dpkg-shlibdeps (dpkg-dev, which build-essential
# brings); the caption's default font is found at run time, so it is named by hand.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "fonts-dejavu-core")
set(CPACK_STRIP_FILES ON)
include(CPack)
