# svetlo_warnings: an interface target every svetlo target links to get the same warnings.
add_library(svetlo_warnings INTERFACE)
target_compile_options(svetlo_warnings INTERFACE
    -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wcast-align
    -Wunused -Woverloaded-virtual -Wnull-dereference -Wformat=2)
if(SVETLO_NATIVE)
    target_compile_options(svetlo_warnings INTERFACE -march=native)
endif()
