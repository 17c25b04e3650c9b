# The Debian package (CPack): the programs, the systemd units and drop-ins, the lab file,
# the calibration, the sound bank and the docs, installed under /usr (the lab file under
# /etc, a conffile). `cpack -G DEB` in the build folder, or deploy/check-package.sh, which
# also runs lintian and checks the unpacked package.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME igms)
set(CPACK_PACKAGE_VENDOR "IGMS")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "IGMS maintainers <igms-maintainers@lists.example.org>")
# MIT (Debian: Expat). The package carries it as /usr/share/doc/igms/copyright
# (deploy/debian/copyright, machine-readable), not as a second licence file.
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Interactive Graphical Modelling System")
set(CPACK_PACKAGE_DESCRIPTION
    "An operator models a remote site from stereo video: marks four points around\n\
a pipe or a block with a 3D pointer, ranger, viewer buttons and voice, and the\n\
vision system finds its pose and size. Networked processes: video, object and\n\
sound servers, one daemon per serial device (each also simulated) and the\n\
control client, started by systemd units (igms@NAME.service) from one lab\n\
file, /etc/igms/lab.yaml.")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
# Installed with DESTDIR and the real prefix, so the units and the lab file name /usr and /etc.
set(CPACK_SET_DESTDIR ON)
set(CPACK_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# Packages the programs run, not link: the speech model and the recogniser's data.
set(CPACK_DEBIAN_PACKAGE_DEPENDS "pocketsphinx-en-us")
set(CPACK_DEBIAN_PACKAGE_HOMEPAGE "https://example.org/igms")
# The lab file is the administrator's to edit: a conffile, kept on upgrade.
set(igms_package_dir ${CMAKE_BINARY_DIR}/package)
file(WRITE ${igms_package_dir}/conffiles "/etc/igms/lab.yaml\n")
# The maintainer scripts: postinst makes the sysusers.d groups (where systemd-sysusers
# exists) and reloads a running systemd; postrm reloads it after removal.
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA ${igms_package_dir}/conffiles
    ${PROJECT_SOURCE_DIR}/deploy/debian/postinst ${PROJECT_SOURCE_DIR}/deploy/debian/postrm)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
include(CPack)
