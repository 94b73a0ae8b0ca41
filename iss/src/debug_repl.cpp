// The debugger's input loops: interactive (libedit line editing and history) and scripted.
#include "iss/debugger.hpp"

#include "base/read_file.hpp"

#include <editline/readline.h>

#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace nesshi::iss {

void debug_interactive(Debugger& d) {
    while (true) {
        char* line = readline("(nesshi) ");
        if (!line) { // end of input
            std::fputs("\n", stdout);
            return;
        }
        std::string text(line);
        std::free(line);
        if (text.find_first_not_of(" \t") != std::string::npos) add_history(text.c_str());
        if (!d.execute(text)) return;
    }
}

void debug_script(Debugger& d, const std::string& path, std::FILE* out) {
    std::istringstream in(base::read_file(path));
    std::string line;
    while (std::getline(in, line)) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        fmt::print(out, "(nesshi) {}\n", line);
        if (!d.execute(line)) return;
    }
}

} // namespace nesshi::iss
