// Compiled runs built at run time (runtime_compile.hpp).
#include "runtime_compile.hpp"

#include "iss/compiled_emit.hpp"
#include "iss/program.hpp"

#include "base/cache_dir.hpp"
#include "base/hash.hpp"
#include "base/write_file.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <dlfcn.h>
#include <elf.h>
#include <fcntl.h>
#include <filesystem>
#include <fstream> // whole_elf reads the headers
#include <memory>
#include <mutex>
#include <optional>
#include <spawn.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/utsname.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <unordered_map>
#include <utility>

extern char** environ;

namespace nesshi::iss {

struct RuntimeCompiled {
    std::string name; // in the cache folder of this build: the program's hash and size
    std::atomic<const CompiledProgram*> table{nullptr};
    std::atomic<uint64_t> cycles{0};
    std::atomic<bool> requested{false};
    uint64_t hash = 0;
    uint32_t bundles = 0;
};

namespace detail {
namespace {

namespace fs = std::filesystem;

// About half a second of one processor on the interpreter: a run shorter than that is not worth a
// compilation of 10-60 s, a longer one (a sweep's cells, the paper) gets faster from then on.
constexpr uint64_t kHotCycles = uint64_t{1} << 26;
// `s` as a whole decimal number, if it is one.
std::optional<uint64_t> whole_number(std::string_view s) {
    uint64_t n = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), n);
    if (s.empty() || ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
    return n;
}

// The mode, and under Wait the cycles after which a program is compiled; `bad`: a value of
// NESSHI_RUNTIME_COMPILE that means none of them (the default applies, with a warning).
struct ModeSetting {
    RuntimeCompile mode = RuntimeCompile::Background;
    uint64_t after = 0;
    bool bad = false;
};
ModeSetting from_environment() {
    const char* v = std::getenv("NESSHI_RUNTIME_COMPILE");
    if (!v) return {};
    const std::string_view s(v);
    if (s == "0") return {RuntimeCompile::Off, 0};
    if (s == "1") return {};
    if (s == "wait") return {RuntimeCompile::Wait, 0};
    if (s.starts_with("wait:"))
        if (const std::optional<uint64_t> n = whole_number(s.substr(5))) return {RuntimeCompile::Wait, *n};
    return {RuntimeCompile::Background, 0, true};
}
const ModeSetting kEnvironment = from_environment();

// The objects of one build stay within this many bytes together, the least recently loaded
// removed first (one object per hot program, 0.1-1.5 MB: a sweep over 100 machine descriptions
// leaves about 200 MB): NESSHI_COMPILED_CACHE_MB, default 1024; `bad`: a value that is no number.
struct CacheLimit {
    uint64_t bytes = uint64_t{1024} << 20;
    bool bad = false;
};
CacheLimit cache_limit_from_environment() {
    const char* v = std::getenv("NESSHI_COMPILED_CACHE_MB");
    if (!v) return {};
    const std::optional<uint64_t> mb = whole_number(v);
    if (!mb || *mb > (uint64_t{1} << 40)) return {CacheLimit{}.bytes, true};
    return {*mb << 20, false};
}
const CacheLimit kCacheLimit = cache_limit_from_environment();
std::atomic<RuntimeCompile> mode{kEnvironment.mode};
std::atomic<uint64_t> wait_after{kEnvironment.after};

bool runnable(const std::string& cmd) {
    if (cmd.find('/') != std::string::npos) return ::access(cmd.c_str(), X_OK) == 0;
    const char* path = std::getenv("PATH");
    for (std::string_view rest = path ? path : ""; !rest.empty();) {
        const size_t colon = rest.find(':');
        const std::string dir(rest.substr(0, colon));
        if (::access(((dir.empty() ? "." : dir) + "/" + cmd).c_str(), X_OK) == 0) return true;
        rest = colon == std::string_view::npos ? std::string_view() : rest.substr(colon + 1);
    }
    return false;
}

std::string quoted(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// The compiler's flags for a program of `bundles` bundles: NESSHI_RUNTIME_FLAGS (-O1), and -O2 up to
// kO2Bundles. Measured with clang 14: a sequential machine's kernels (tree on model M, a copy of
// `seq`; 320 and 530 bundles) ran 1.37x the built-in runs' CPU time at -O1 and 1.13x at -O2, for
// a tenth more compile time; the IC's kernel on `ic-real` (2,097 bundles) ran no faster at -O2
// and compiled a quarter longer.
constexpr uint32_t kO2Bundles = 1000;
std::string flags_for(uint32_t bundles) {
    return fmt::format("{}{}", NESSHI_RUNTIME_FLAGS, bundles <= kO2Bundles ? " -O2" : "");
}

// What every program shares, found once: the cache folder, the compiler and what it compiles
// against. Each build (its sources, compiler and flags) has a folder of its own in the cache.
struct Setup {
    std::string dir;      // the cache; empty: none, nothing compiled
    std::string compiler; // empty: none found
    std::string no_compiler; // then why, when the user named one
    std::string key;      // hex key of the embedded sources, the compiler and the flags
    std::string build;    // dir/key
    std::string includes; // build/include: the embedded headers, written on first use
};

const Setup& setup() {
    static const Setup& s = *[] { // never freed: a compilation's thread may outlive main
        auto* p = new Setup;
        Setup& r = *p;
        r.dir = base::user_cache_dir("compiled");
        // clang++ first: it compiles these runs 7x faster than g++ at -O1 (17 s against 126 s for
        // the 1,948 bundles of the IC's loop kernel on a user's machine), and they run as fast.
        if (const char* c = std::getenv("NESSHI_CXX"); c && *c) r.compiler = c;
        else if (runnable("clang++")) r.compiler = "clang++";
        else if (runnable(NESSHI_RUNTIME_CXX)) r.compiler = NESSHI_RUNTIME_CXX;
        else r.compiler = "c++";
        if (!runnable(r.compiler)) {
            if (std::getenv("NESSHI_CXX"))
                r.no_compiler = fmt::format("NESSHI_CXX={} is not a program found on PATH (a compiler with options "
                                            "needs a script of its own)",
                                            r.compiler);
            r.compiler.clear();
        }
        base::Fnv1a h;
        for (const EmbeddedFile& f : runtime_sources()) h.add(f.path).add(std::string_view("\0", 1)).add(f.text);
        utsname host{};
        ::uname(&host); // a home folder shared by hosts of two architectures keeps both objects
        h.add(r.compiler).add(flags_for(0)).add(flags_for(~0u)).add(std::to_string(kO2Bundles));
        h.add(std::string_view(host.machine));
        r.key = base::hex64(h.value());
        r.build = r.dir + "/" + r.key;
        r.includes = r.build + "/include";
        return p;
    }();
    return s;
}

std::mutex registry_mutex;
std::unordered_map<std::string, RuntimeCompiled*>& registry() {
    static auto* r = new std::unordered_map<std::string, RuntimeCompiled*>; // never freed: threads may outlive main
    return *r;
}

// One warning of each kind per process (a sweep loads many programs); `kind` is a literal.
void warn_once(const char* kind, const std::string& what) {
    static std::mutex mutex;
    static auto* warned = new std::vector<const char*>; // never freed: threads may outlive main
    std::lock_guard lock(mutex);
    if (std::find(warned->begin(), warned->end(), kind) != warned->end()) return;
    warned->push_back(kind);
    std::fprintf(stderr, "nesshi: %s\n", what.c_str());
}
constexpr const char* kInterpreted = "; those programs run on the interpreter";

std::string so_path(const RuntimeCompiled& e) { return setup().build + "/" + e.name + ".so"; }

// Whether `path` holds every byte its ELF headers promise: dlopen maps a truncated object and
// dies of SIGBUS on its first touch past the end. (We only ever rename a whole object into the
// cache; this is for damage from outside.)
bool whole_elf(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    Elf64_Ehdr eh{};
    if (!in.read(reinterpret_cast<char*>(&eh), sizeof eh) || std::memcmp(eh.e_ident, ELFMAG, SELFMAG) != 0 ||
        eh.e_ident[EI_CLASS] != ELFCLASS64 || eh.e_phentsize != sizeof(Elf64_Phdr))
        return false;
    std::error_code ec;
    const uint64_t size = fs::file_size(path, ec);
    if (ec || eh.e_shoff + uint64_t{eh.e_shnum} * eh.e_shentsize > size) return false;
    for (uint32_t i = 0; i < eh.e_phnum; ++i) {
        Elf64_Phdr ph{};
        if (!in.seekg(std::streamoff(eh.e_phoff + uint64_t{i} * sizeof ph)) || !in.read(reinterpret_cast<char*>(&ph), sizeof ph) ||
            ph.p_offset + ph.p_filesz > size)
            return false;
    }
    return true;
}

// Loads the cached runs of `e` when there are some; true when its table is set. A damaged object
// is removed (and compiled again when the program is hot).
bool load(RuntimeCompiled& e) {
    const std::string path = so_path(e);
    if (::access(path.c_str(), R_OK) != 0) return false;
    if (!whole_elf(path)) {
        if (::access(path.c_str(), F_OK) != 0) return false; // removed meanwhile (trim_cache_files elsewhere)
        warn_once("damaged", fmt::format("removed damaged compiled runs {}; they are compiled again", path));
        std::error_code ec;
        fs::remove(path, ec);
        return false;
    }
    void* h = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        if (::access(path.c_str(), F_OK) != 0) return false; // removed meanwhile (trim_cache_files elsewhere)
        warn_once("load", fmt::format("cannot load compiled runs {} ({}){}", path, ::dlerror(), kInterpreted));
        return false;
    }
    using Get = const CompiledProgram* (*)();
    const auto get = reinterpret_cast<Get>(::dlsym(h, "nesshi_compiled_program"));
    const CompiledProgram* t = get ? get() : nullptr;
    if (!t || t->hash != e.hash || t->bundles != e.bundles) {
        ::dlclose(h);
        return false;
    }
    e.table.store(t, std::memory_order_release); // the object stays loaded for the process's life
    base::touch_cache_file(path); // recently used: trimming the cache keeps it
    return true;
}

// The embedded headers under setup().includes, written once (into a folder of their own first,
// renamed into place, so that a reader never sees half of them).
bool write_includes() {
    const Setup& s = setup();
    std::error_code ec;
    if (fs::is_directory(s.includes, ec)) return true;
    const std::string tmp = fmt::format("{}.tmp-{}-{}", s.includes, ::getpid(), std::hash<std::thread::id>{}(std::this_thread::get_id()));
    try {
        for (const EmbeddedFile& f : runtime_sources()) {
            const fs::path p = fs::path(tmp) / f.path;
            fs::create_directories(p.parent_path());
            base::write_file(p.string(), f.text);
        }
    } catch (const std::exception&) {
        fs::remove_all(tmp, ec);
        return false;
    }
    fs::rename(tmp, s.includes, ec);
    if (ec) fs::remove_all(tmp, ec); // another process was first
    return fs::is_directory(s.includes, ec);
}

// Background compilations that have not started their compiler yet. A process that exits waits
// for them to start it (writing the sources takes milliseconds), not for the compiler, which
// outlives the process: a run of a second compiles for the next one.
struct Starting {
    std::mutex mutex;
    std::condition_variable cv;
    int count = 0;
};
Starting& starting() {
    static auto* s = new Starting; // never freed: a compilation's thread may outlive main
    return *s;
}
struct WaitForStartsAtExit {
    ~WaitForStartsAtExit() {
        std::unique_lock lock(starting().mutex);
        starting().cv.wait_for(lock, std::chrono::seconds(10), [] { return starting().count == 0; });
    }
};
// One compilation until its compiler has started or it gave up (started() is idempotent).
class StartGuard {
  public:
    StartGuard() {
        static WaitForStartsAtExit waiter; // destroyed at exit, before anything it waits for
        std::lock_guard lock(starting().mutex);
        ++starting().count;
    }
    ~StartGuard() { started(); }
    StartGuard(const StartGuard&) = delete;
    StartGuard& operator=(const StartGuard&) = delete;
    void started() {
        if (!std::exchange(on_, false)) return;
        std::lock_guard lock(starting().mutex);
        if (--starting().count == 0) starting().cv.notify_all();
    }

  private:
    bool on_ = true;
};

// Runs `script` with sh in a session of its own (a terminal's hang-up or Ctrl-C does not stop
// it), with default signal handling, its standard streams on /dev/null, the lock `lock_fd` as its
// descriptor 3 (held as long as the shell runs, whatever ends it) and no other descriptor of ours
// (a pipe to a reader must not stay open after we exit); waits for it.
int run_shell(const std::string& script, int lock_fd, StartGuard& start) {
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    for (int fd = 0; fd < 3; ++fd) posix_spawn_file_actions_addopen(&fa, fd, "/dev/null", fd ? O_WRONLY : O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&fa, lock_fd, 3);
    posix_spawn_file_actions_addclosefrom_np(&fa, 4);
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    sigset_t all, none;
    sigfillset(&all);
    sigemptyset(&none);
    posix_spawnattr_setsigdefault(&attr, &all);
    posix_spawnattr_setsigmask(&attr, &none);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSID | POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);
    std::string sh = "sh", c = "-c", body = script;
    char* argv[] = {sh.data(), c.data(), body.data(), nullptr};
    pid_t pid = 0;
    const int rc = ::posix_spawn(&pid, "/bin/sh", &fa, &attr, argv, environ);
    posix_spawnattr_destroy(&attr);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) return -1;
    start.started();
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Compiles `files` (compiled_runs_source's) into the cache and loads them. The lock is a flock on
// <name>.lock, held by the process that compiles and handed to its shell, so that it lasts as
// long as the compilation and goes with it however it ends; another process waits for it, then
// finds the object, or the log of a failure (which compiling again would repeat).
void compile_and_load(RuntimeCompiled& e, const std::vector<std::string>& files, StartGuard& start) {
    const Setup& s = setup();
    static std::once_flag pruned;
    std::call_once(pruned, [&] { base::prune_cache_folders(s.dir, s.key); });
    std::error_code ec;
    fs::create_directories(s.build, ec);
    const std::string lock = s.build + "/" + e.name + ".lock", log = s.build + "/" + e.name + ".log";
    const int fd = ::open(lock.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
    if (fd < 0) return warn_once("lock", fmt::format("cannot write {} ({}){}", lock, std::strerror(errno), kInterpreted));
    struct Close {
        int fd;
        ~Close() { ::close(fd); }
    } close_lock{fd};
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
        start.started(); // another process compiles: nothing of ours to start before an exit
        while (::flock(fd, LOCK_EX) != 0 && errno == EINTR) {}
    }
    if (load(e)) return;
    if (fs::exists(log, ec))
        return warn_once("failed", fmt::format("the runs of a program failed to compile before (see {}; remove it to "
                                               "try again){}",
                                               log, kInterpreted));
    // One compilation at a time in a process: a sweep may find many programs hot at once.
    static std::mutex one_at_a_time;
    std::unique_lock turn(one_at_a_time, std::try_to_lock);
    if (!turn.owns_lock()) {
        start.started(); // queued: an exit does not wait for it (the next run compiles it)
        turn.lock();
    }
    if (!write_includes())
        return warn_once("headers", fmt::format("cannot write the compiled runs' headers under {}{}", s.build, kInterpreted));
    const std::string work = fmt::format("{}/{}.work-{}", s.build, e.name, ::getpid());
    fs::remove_all(work, ec); // a dead process's of the same pid
    fs::create_directories(work, ec);
    try {
        for (size_t i = 0; i < files.size(); ++i) base::write_file(fmt::format("{}/runs_{}.cpp", work, i), files[i]);
    } catch (const base::WriteError& err) {
        fs::remove_all(work, ec);
        return warn_once("sources", fmt::format("{}{}", err.what(), kInterpreted));
    }
    // The parts compile side by side; the shell links and renames, so that a compilation
    // outlives a process that exits first.
    const std::string script = fmt::format(
        "cd {work} || exit 1; for f in runs_*.cpp; do "
        "(nice -n 10 {cxx} {flags} -I{inc}/iss/src -I{inc}/iss/include -I{inc}/isa/include -I{inc}/base/include "
        "-c $f -o $f.o >$f.log 2>&1 || touch failed) & done; wait; "
        "[ ! -e failed ] && {cxx} -shared runs_*.o -o runs.so >link.log 2>&1 && mv runs.so {so}; st=$?; "
        "[ $st = 0 ] || cat *.log >{log}; cd / && rm -rf {work}; exit $st",
        fmt::arg("work", quoted(work)), fmt::arg("cxx", quoted(s.compiler)), fmt::arg("flags", flags_for(e.bundles)),
        fmt::arg("inc", quoted(s.includes)), fmt::arg("so", quoted(so_path(e))), fmt::arg("log", quoted(log)));
    if (run_shell(script, fd, start) != 0 || !load(e))
        return warn_once("compile", fmt::format("compiling the runs of a program failed (see {}){}", log, kInterpreted));
    // An object whose lock another process holds is being compiled or loaded: it stays.
    base::trim_cache_files(s.build, ".so", kCacheLimit.bytes, e.name + ".so", [&](const std::string& so) {
        const std::string other = s.build + "/" + so.substr(0, so.size() - 3) + ".lock";
        const int lfd = ::open(other.c_str(), O_RDWR | O_CLOEXEC);
        if (lfd < 0) return false; // no lock file: nobody compiles it
        const bool held = ::flock(lfd, LOCK_EX | LOCK_NB) != 0;
        ::close(lfd);
        return held;
    });
}

} // namespace

RuntimeCompiled* runtime_compiled_for(uint64_t decoded_hash, uint32_t bundles) {
    if (kEnvironment.bad)
        warn_once("mode", fmt::format("NESSHI_RUNTIME_COMPILE={} is none of 0, 1, wait or wait:N; taken as 1",
                                      std::getenv("NESSHI_RUNTIME_COMPILE")));
    if (kCacheLimit.bad)
        warn_once("limit", fmt::format("NESSHI_COMPILED_CACHE_MB={} is not a number of megabytes; taken as {}",
                                       std::getenv("NESSHI_COMPILED_CACHE_MB"), CacheLimit{}.bytes >> 20));
    if (mode.load() == RuntimeCompile::Off || setup().dir.empty()) return nullptr;
    const std::string name = fmt::format("{:016x}-{}", decoded_hash, bundles);
    std::lock_guard lock(registry_mutex);
    RuntimeCompiled*& e = registry()[name];
    if (!e) {
        e = new RuntimeCompiled;
        e->name = name;
        e->hash = decoded_hash;
        e->bundles = bundles;
        load(*e);
    }
    return e;
}

const CompiledProgram* runtime_table(const RuntimeCompiled& e) { return e.table.load(std::memory_order_acquire); }

const CompiledProgram* runtime_ran(RuntimeCompiled& e, const Program& prog, uint64_t cycles) {
    if (const CompiledProgram* t = runtime_table(e)) return t;
    const RuntimeCompile m = mode.load();
    const uint64_t total = e.cycles.fetch_add(cycles, std::memory_order_relaxed) + cycles;
    if (m == RuntimeCompile::Off || total < (m == RuntimeCompile::Wait ? wait_after.load() : kHotCycles)) return nullptr;
    if (e.requested.exchange(true)) return runtime_table(e);
    if (setup().compiler.empty()) {
        if (!setup().no_compiler.empty()) warn_once("compiler", setup().no_compiler + kInterpreted);
        return nullptr;
    }
    std::vector<std::string> files;
    try {
        const std::string id = "rt_" + base::hex64(e.hash);
        const uint32_t parts = std::clamp(std::thread::hardware_concurrency(), 1u, 8u); // compiled side by side
        files = compiled_runs_source(prog, e.name + " (compiled at run time)", id, parts, "nesshi::iss::runtime");
        files[0] += fmt::format("\nextern \"C\" __attribute__((visibility(\"default\"))) const nesshi::iss::CompiledProgram* "
                                "nesshi_compiled_program() {{ return &nesshi::iss::runtime::kCompiled_{}; }}\n",
                                id);
    } catch (const std::exception&) {
        return nullptr; // a program the compiled form cannot hold runs on the interpreter
    }
    if (m == RuntimeCompile::Wait) {
        StartGuard start;
        compile_and_load(e, files, start);
    } else {
        try {
            auto start = std::make_shared<StartGuard>();
            std::thread([&e, files = std::move(files), start] { compile_and_load(e, files, *start); }).detach();
        } catch (const std::system_error& err) { // no thread to be had: the interpreter goes on
            warn_once("thread", fmt::format("cannot start a compilation ({}){}", err.what(), kInterpreted));
        }
    }
    return runtime_table(e);
}

} // namespace detail

RuntimeCompile runtime_compile_mode() { return detail::mode.load(); }
void set_runtime_compile_mode(RuntimeCompile m, uint64_t wait_after) {
    detail::mode.store(m);
    detail::wait_after.store(wait_after);
}

} // namespace nesshi::iss
