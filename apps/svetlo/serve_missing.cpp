// svetlo serve in a build without cpp-httplib (scripts/setup installs libcpp-httplib-dev).
#include "commands.h"
#include "svetlo/core/error.h"

namespace svetlo {

int run_serve(const ServeArgs&) {
    throw Error("svetlo", "serve", "not built: this build has no cpp-httplib (libcpp-httplib-dev)");
}

}  // namespace svetlo
