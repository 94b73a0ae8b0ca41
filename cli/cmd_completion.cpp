// `nesshi completion bash|zsh|commands`: shell completion written from the command tree itself
// (so it cannot drift from the commands), and the list of command paths the man pages are made for.
#include "commands.hpp"
#include "errors.hpp"

#include "isa/machine.hpp"

#include <fmt/format.h>

#include <set>
#include <string>
#include <vector>

namespace nesshi::cli {
namespace {

// One command of the tree: its path below `nesshi` ("paper gaps"), subcommands and options.
struct Command {
    std::string path;
    std::string description;
    std::vector<const CLI::App*> subs;
    std::vector<const CLI::Option*> options;
};

bool hidden(const CLI::App& c) { return c.get_group().empty(); }
bool takes_value(const CLI::Option& o) { return o.get_type_size_max() > 0; }
std::string first_line(const std::string& s) { return s.substr(0, s.find('\n')); }

void collect(const CLI::App& app, const std::string& path, std::vector<Command>& out) {
    Command c{path, first_line(app.get_description()), {}, {}};
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
        if (!hidden(*sub)) c.subs.push_back(sub);
    for (const CLI::Option* o : app.get_options())
        if (o->nonpositional() && !o->get_group().empty()) c.options.push_back(o);
    out.push_back(c);
    for (const CLI::App* sub : c.subs) collect(*sub, path.empty() ? sub->get_name() : path + " " + sub->get_name(), out);
}

std::vector<std::string> spellings(const CLI::Option& o) {
    std::vector<std::string> names;
    for (const std::string& s : o.get_snames()) names.push_back("-" + s);
    for (const std::string& l : o.get_lnames()) names.push_back("--" + l);
    return names;
}

// Values a user would type after an option, where the tool knows them: machines and scenes.
std::string value_words(const CLI::Option& o) {
    const std::string name = o.get_name(false, true);
    if (name.ends_with("machine")) return fmt::format("{}", fmt::join(isa::preset_names(), " "));
    if (name == "--model") return "S M V";
    return "";
}

std::string case_pattern(const std::string& path) {
    std::string p = "/" + path;
    for (char& ch : p) if (ch == ' ') ch = '/';
    return path.empty() ? "" : p;
}

// Every subcommand's path as a shell case pattern, "/asm|/scene/info|...": the words a completer
// steps through before it completes.
std::string every_path(const std::vector<Command>& tree) {
    std::vector<std::string> paths;
    for (const Command& c : tree) if (!c.path.empty()) paths.push_back(case_pattern(c.path));
    return fmt::format("{}", fmt::join(paths, "|"));
}

void print_bash(const std::vector<Command>& tree) {
    fmt::print("# bash completion for nesshi; made by `nesshi completion bash` from the command tree.\n");
    fmt::print("_nesshi() {{\n");
    fmt::print("    local cur=\"${{COMP_WORDS[COMP_CWORD]}}\" prev=\"${{COMP_WORDS[COMP_CWORD-1]}}\" path=\"\" i\n");
    fmt::print("    for ((i = 1; i < COMP_CWORD; i++)); do\n        case \"$path/${{COMP_WORDS[i]}}\" in\n");
    fmt::print("            {}) path=\"$path/${{COMP_WORDS[i]}}\" ;;\n", every_path(tree));
    fmt::print("        esac\n    done\n");
    // An option's own values after it, where known.
    fmt::print("    case \"$prev\" in\n");
    std::set<std::string> done;
    for (const Command& c : tree)
        for (const CLI::Option* o : c.options)
            if (const std::string words = value_words(*o); !words.empty() && done.insert(o->get_name(true, true)).second)
                fmt::print("        {}) COMPREPLY=($(compgen -W \"{} $(compgen -f -- \"$cur\")\" -- \"$cur\")); return ;;\n",
                           fmt::join(spellings(*o), "|"), words);
    fmt::print("    esac\n");
    fmt::print("    local subs=\"\" opts=\"\"\n    case \"$path\" in\n");
    for (const Command& c : tree) {
        std::vector<std::string> subs, opts;
        for (const CLI::App* s : c.subs) subs.push_back(s->get_name());
        for (const CLI::Option* o : c.options)
            for (const std::string& n : spellings(*o)) opts.push_back(n);
        fmt::print("        \"{}\") subs=\"{}\" opts=\"{}\" ;;\n", case_pattern(c.path), fmt::join(subs, " "),
                   fmt::join(opts, " "));
    }
    fmt::print("    esac\n");
    fmt::print("    if [[ \"$cur\" == -* ]]; then\n        COMPREPLY=($(compgen -W \"$opts\" -- \"$cur\"))\n");
    fmt::print("    elif [[ -n \"$subs\" ]]; then\n        COMPREPLY=($(compgen -W \"$subs\" -- \"$cur\"))\n");
    fmt::print("    fi\n}}\ncomplete -o default -o bashdefault -F _nesshi nesshi\n");
}

std::string zsh_quote(std::string s) {
    std::string out;
    for (char ch : s) {
        if (ch == '\'') out += "'\\''";
        else if (ch == '[' || ch == ']' || ch == ':' || ch == '\\') { out += '\\'; out += ch; }
        else out += ch;
    }
    return out;
}

void print_zsh(const std::vector<Command>& tree) {
    fmt::print("#compdef nesshi\n# zsh completion for nesshi; made by `nesshi completion zsh` from the command tree.\n");
    fmt::print("_nesshi() {{\n    local p=\"\" depth=1 i\n");
    fmt::print("    for ((i = 2; i < CURRENT; i++)); do\n        case \"$p/${{words[i]}}\" in\n");
    fmt::print("            ({}) p=\"$p/${{words[i]}}\"; depth=$i ;;\n", every_path(tree));
    fmt::print("        esac\n    done\n");
    fmt::print("    local -a subs opts\n    case \"$p\" in\n");
    for (const Command& c : tree) {
        fmt::print("        (\"{}\")\n            subs=(", case_pattern(c.path));
        for (const CLI::App* s : c.subs)
            fmt::print(" '{}:{}'", s->get_name(), zsh_quote(first_line(s->get_description())));
        fmt::print(" )\n            opts=(");
        for (const CLI::Option* o : c.options) {
            const std::string desc = zsh_quote(first_line(o->get_description()));
            std::string values = value_words(*o);
            for (const std::string& n : spellings(*o)) {
                if (!takes_value(*o)) fmt::print(" '{}[{}]'", n, desc);
                else if (!values.empty()) fmt::print(" '{}[{}]:value:({})'", n, desc, values);
                else fmt::print(" '{}[{}]:value:_files'", n, desc);
            }
        }
        fmt::print(" ) ;;\n");
    }
    fmt::print("    esac\n");
    fmt::print("    shift $((depth - 1)) words\n    (( CURRENT -= depth - 1 ))\n");
    fmt::print("    if (( ${{#subs}} )) && [[ $PREFIX != -* ]]; then\n        _describe -t commands 'nesshi command' subs\n");
    fmt::print("    else\n        _arguments -s : $opts '*:file:_files'\n    fi\n}}\n");
    fmt::print("if [[ $zsh_eval_context[-1] == loadautofunc ]]; then _nesshi \"$@\"; else compdef _nesshi nesshi; fi\n");
}

} // namespace

void add_completion(CLI::App& app) {
    auto* cmd = app.add_subcommand("completion", "Print shell completion for bash or zsh (source <(nesshi completion bash))");
    auto shell = std::make_shared<std::string>();
    cmd->add_option("shell", *shell, "bash, zsh, or commands (every command path, one a line: what man pages are made for)")
        ->required()
        ->check(CLI::IsMember({"bash", "zsh", "commands"}));
    cmd->callback([&app, shell] {
        std::vector<Command> tree;
        collect(app, "", tree);
        if (*shell == "bash") print_bash(tree);
        else if (*shell == "zsh") print_zsh(tree);
        else
            for (const Command& c : tree) if (!c.path.empty()) fmt::print("{}\n", c.path);
    });
}

} // namespace nesshi::cli
