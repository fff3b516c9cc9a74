# Writes the man page wavecam.1.gz from the command's own help (cmake -P, at build time):
# help2man reads `wavecam --help` and `wavecam --version`; each command's --help follows as
# a section of its own, preformatted. Usage:
#   cmake -DHELP2MAN=help2man -DWAVECAM=path/to/wavecam -DOUT=wavecam.1 -P man_page.cmake
set(include_file "${OUT}.include")
set(text "[COMMANDS]\n")
foreach(command psf apply estimate sweep merge farm)
  execute_process(COMMAND ${WAVECAM} ${command} --help OUTPUT_VARIABLE help RESULT_VARIABLE status)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "wavecam ${command} --help failed (${status})")
  endif()
  string(REPLACE "${WAVECAM}" "wavecam" help "${help}")  # the usage line names the program as run
  # roff: a backslash is \e, a minus sign \- (a bare - is a hyphen); a line may not begin
  # with a control character
  string(REPLACE "\\" "\\e" help "${help}")
  string(REPLACE "-" "\\-" help "${help}")
  string(REGEX REPLACE "(^|\n)([.'])" "\\1\\\\&\\2" help "${help}")
  string(APPEND text ".SS \"wavecam ${command}\"\n.nf\n${help}.fi\n")
endforeach()
file(WRITE "${include_file}" "${text}")
execute_process(COMMAND ${HELP2MAN} --no-info --section=1 "--name=a wave-optics pinhole camera"
                        --include=${include_file} --output=${OUT} ${WAVECAM}
                RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "help2man failed (${status})")
endif()
execute_process(COMMAND gzip -9nf ${OUT} RESULT_VARIABLE status)  # -n: no time stamp, reproducible
if(NOT status EQUAL 0)
  message(FATAL_ERROR "gzip ${OUT} failed (${status})")
endif()
