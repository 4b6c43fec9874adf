# The man page and the user guide, both made from the sources the program itself uses:
# - spectralize.1, written at build time by `spectralize --help-man` (the settings schema),
#   installed under share/man/man1;
# - the Sphinx guide (`cmake --build . --target docs`, `make docs`): docs/ copied into the
#   build tree with the flag chapter `spectralize --help-markdown` writes, the Python API
#   reference imported from the built module; HTML into build/docs/html with warnings as
#   errors, installed under share/doc/spectralize/html when built.
set(SPECTRALIZE_DOCS_DIR "${PROJECT_BINARY_DIR}/docs")
add_custom_command(OUTPUT "${SPECTRALIZE_DOCS_DIR}/spectralize.1"
  COMMAND ${CMAKE_COMMAND} -E make_directory "${SPECTRALIZE_DOCS_DIR}"
  COMMAND sh -c "\"$1\" --help-man > \"$2.tmp\" && mv \"$2.tmp\" \"$2\"" man
          "$<TARGET_FILE:spectralize>" "${SPECTRALIZE_DOCS_DIR}/spectralize.1"
  DEPENDS spectralize
  COMMENT "spectralize.1 from the settings schema"
  VERBATIM)
add_custom_target(man_page ALL DEPENDS "${SPECTRALIZE_DOCS_DIR}/spectralize.1")
install(FILES "${SPECTRALIZE_DOCS_DIR}/spectralize.1" DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)

find_program(SPHINX_BUILD_EXECUTABLE sphinx-build)
if(SPHINX_BUILD_EXECUTABLE)
  set(guide_source "${SPECTRALIZE_DOCS_DIR}/source")
  add_custom_target(docs
    COMMAND ${CMAKE_COMMAND} -E rm -rf "${guide_source}"
    COMMAND ${CMAKE_COMMAND} -E copy_directory "${PROJECT_SOURCE_DIR}/docs" "${guide_source}"
    COMMAND sh -c "\"$1\" --help-markdown > \"$2\"" flags "$<TARGET_FILE:spectralize>"
            "${guide_source}/guide/flags.md"
    COMMAND sh -c "mkdir -p \"$2\" && for c in image to-rgb color plot plot-pixel ingest table; do \"$1\" --help-markdown-for $c > \"$2/$c.md\" || exit 1; done"
            flags "$<TARGET_FILE:spectralize>" "${guide_source}/guide/flags"
    COMMAND ${CMAKE_COMMAND} -E env "PYTHONPATH=${PROJECT_BINARY_DIR}/python"
            ${SPHINX_BUILD_EXECUTABLE} -W --keep-going -q -b html -d "${SPECTRALIZE_DOCS_DIR}/doctrees"
            "${guide_source}" "${SPECTRALIZE_DOCS_DIR}/html"
    COMMENT "The user guide (Sphinx, warnings as errors) into ${SPECTRALIZE_DOCS_DIR}/html"
    VERBATIM)
  add_dependencies(docs spectralize man_page)
  if(TARGET spectralize_python)
    add_dependencies(docs spectralize_python)
  endif()
else()
  message(STATUS "sphinx-build not found: `make docs` (the user guide) is not available")
endif()
install(DIRECTORY "${SPECTRALIZE_DOCS_DIR}/html/" DESTINATION ${CMAKE_INSTALL_DOCDIR}/html
        OPTIONAL PATTERN ".buildinfo" EXCLUDE PATTERN ".doctrees" EXCLUDE)
