# `cmake --install build --prefix P`: the lobe binary in P/bin, the data it needs at run time
# (assets/: scenes, CThead, brain volumes, with their READMEs and licences) in
# P/share/lobe/assets, where apps/data_dir.h finds it relative to the executable. Fonts come from
# Debian (fonts-dejavu-core). The libraries are static and not installed.
include(GNUInstallDirs)
install(TARGETS lobe RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/assets/ DESTINATION ${CMAKE_INSTALL_DATADIR}/lobe/assets)
# The user guide and its pages in P/share/doc/lobe: README.md beside docs/, so the README's links
# (docs/…, docs/images/…) hold in the installed copy too.
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/lobe)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/lobe/docs)
