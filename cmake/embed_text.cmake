# cmake -DINPUT=FILE -DOUTPUT=FILE.cpp -DNAME=SYMBOL -P embed_text.cmake: writes a C++ source
# defining `const char lobe::SYMBOL[]` as FILE's text (a raw string literal), so a text resource
# (the study page template, study/study_page.html) is compiled into the program.
file(READ "${INPUT}" text)
string(FIND "${text}" ")lobe_embed\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "${INPUT} contains the raw-string delimiter )lobe_embed\"")
endif()
file(WRITE "${OUTPUT}.tmp" "// Generated from ${INPUT} by cmake/embed_text.cmake: do not edit.\n"
  "namespace lobe {\nextern const char ${NAME}[];\nconst char ${NAME}[] = R\"lobe_embed(${text})lobe_embed\";\n}\n")
file(RENAME "${OUTPUT}.tmp" "${OUTPUT}")
