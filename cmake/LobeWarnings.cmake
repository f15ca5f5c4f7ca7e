# lobe_set_warnings(target): the project's warning level, applied to our own targets only.
function(lobe_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wno-deprecated-declarations)
endfunction()
