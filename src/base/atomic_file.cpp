// The atomic writer (see atomic_file.hpp): temporaries, their cleanup on signals and the next
// run, and the rename when complete.
#include "base/atomic_file.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/time.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <set>
#include <system_error>

#include "base/errors.hpp"

namespace carve {

namespace {

constexpr const char* kPrefix = ".carve-tmp-";

// Temporaries the signal handler removes. Fixed storage: the handler may only touch memory
// that is never allocated or freed while it could run. Zero at compile time (constinit): set at
// start-up, the 64 states 4 kB apart cost 64 page faults in every run, 12 % of the faults of
// `carve --version` (perf record -e page-faults).
constexpr int kSlots = 64;
constexpr size_t kPathMax = 4096;
struct Slot {
    std::atomic<int> state{0};  // 0 free, 1 claimed, 2 file, 3 folder
    char path[kPathMax];
};
constinit Slot g_slots[kSlots]{};
mode_t g_umask = 022;  // read once at start-up (umask() cannot be read without setting it)

int claim(const std::string& path, bool folder) {
    if (path.size() >= kPathMax) return -1;
    for (int i = 0; i < kSlots; ++i) {
        int expected = 0;
        if (g_slots[i].state.compare_exchange_strong(expected, 1)) {
            std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
            g_slots[i].state.store(folder ? 3 : 2, std::memory_order_release);
            return i;
        }
    }
    return -1;  // over 64 at once: a signal then leaves it for the next run to remove
}

void release(int slot) {
    if (slot >= 0) g_slots[slot].state.store(0, std::memory_order_release);
}

// Async-signal-safe: raw system calls only (getdents64, unlinkat, rmdir).
void remove_folder_raw(const char* path) {
    const int fd = ::open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0) {
        alignas(8) char buf[8192];
        for (;;) {
            const long n = ::syscall(SYS_getdents64, fd, buf, sizeof buf);
            if (n <= 0) break;
            for (long off = 0; off < n;) {
                struct Entry {
                    unsigned long long ino;
                    long long off;
                    unsigned short reclen;
                    unsigned char type;
                    char name[1];
                };
                const Entry* e = reinterpret_cast<const Entry*>(buf + off);
                if (std::strcmp(e->name, ".") != 0 && std::strcmp(e->name, "..") != 0)
                    ::unlinkat(fd, e->name, 0);
                off += e->reclen;
            }
        }
        ::close(fd);
    }
    ::rmdir(path);
}

void remove_registered() {
    for (Slot& s : g_slots) {
        const int state = s.state.load(std::memory_order_acquire);
        if (state == 2) ::unlink(s.path);
        if (state == 3) {
            // Worker threads go on writing pictures into the folder while this handler runs on
            // one thread: a file created between the listing and rmdir kept the folder. Renamed
            // first, the folder takes no new file (the workers open the old path), and what is
            // in it goes with it. The new name still matches the stale pattern of the next run.
            static char moved[kPathMax + 8];
            const size_t n = std::strlen(s.path);
            std::memcpy(moved, s.path, n);
            std::memcpy(moved + n, ".gone", 6);
            remove_folder_raw(::rename(s.path, moved) == 0 ? moved : s.path);
        }
    }
}

void on_signal(int sig) {
    remove_registered();
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

char g_timeout_message[128] = "carve: gave up: --timeout reached\n";

void on_timeout(int) {
    remove_registered();
    const ssize_t ignored =
        ::write(STDERR_FILENO, g_timeout_message, std::strlen(g_timeout_message));
    (void)ignored;
    ::_exit(kExitBadInput);
}

std::string folder_of(const std::string& path) {
    const std::filesystem::path p(path);
    const std::filesystem::path parent = p.parent_path();
    return parent.empty() ? std::string(".") : parent.string();
}

// "<folder>/.carve-tmp-<pid>-XXXXXX" for mkstemp / mkdtemp.
std::string temp_template(const std::string& near_path) {
    return folder_of(near_path) + "/" + kPrefix + std::to_string(::getpid()) + "-XXXXXX";
}

void sync_folder(const std::string& folder) {
    const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    ::fsync(fd);  // the rename itself survives a power cut; best effort
    ::close(fd);
}

// Refuses a target that exists and is not a regular file (a device, a FIFO, a socket, a
// folder): rename would replace the node itself, and writing into it is not what carve does.
void need_regular_or_absent(const std::string& target) {
    struct stat st {};
    if (::stat(target.c_str(), &st) != 0) return;
    if (!S_ISREG(st.st_mode))
        throw OutputError("refusing to write " + target + ": it exists and is not a regular file");
}

}  // namespace

void install_cleanup_handlers() {
    g_umask = ::umask(0);
    ::umask(g_umask);
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0;
    // Every signal whose default ends the process and that can be caught: SIGQUIT and SIGUSR1
    // during the final write left temporaries of several MB (issue #38). SIGPIPE (a closed
    // stdout or report reader) and SIGALRM without --timeout end it too. SIGXFSZ is ignored
    // (cli/main.cpp): the write fails and the writer cleans up.
    for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGPIPE, SIGALRM, SIGVTALRM,
                    SIGPROF, SIGXCPU, SIGIO})
        ::sigaction(sig, &sa, nullptr);
}

void exit_after(double seconds) {
    std::snprintf(g_timeout_message, sizeof g_timeout_message,
                  "carve: gave up after %g s (--timeout); nothing was written\n", seconds);
    struct sigaction sa {};
    sa.sa_handler = on_timeout;
    sigemptyset(&sa.sa_mask);
    ::sigaction(SIGALRM, &sa, nullptr);
    itimerval t{};
    t.it_value.tv_sec = static_cast<time_t>(seconds);
    t.it_value.tv_usec = static_cast<suseconds_t>((seconds - double(t.it_value.tv_sec)) * 1e6);
    if (t.it_value.tv_sec == 0 && t.it_value.tv_usec == 0) t.it_value.tv_usec = 1;
    ::setitimer(ITIMER_REAL, &t, nullptr);
}

void remove_stale_temporaries(const std::string& dir) {
    // Once per folder and run: a raster stack writes thousands of files into one folder, and
    // scanning it again for each would cost the square of their number.
    {
        static std::mutex mutex;
        static std::set<std::string> scanned;
        std::lock_guard lock(mutex);
        if (!scanned.insert(dir).second) return;
    }
    DIR* d = ::opendir(dir.c_str());
    if (!d) return;
    const size_t prefix = std::strlen(kPrefix);
    std::vector<std::string> stale;
    while (const dirent* e = ::readdir(d)) {
        const std::string name = e->d_name;
        if (name.compare(0, prefix, kPrefix) != 0) continue;
        size_t i = prefix;
        long long pid = 0;
        while (i < name.size() && name[i] >= '0' && name[i] <= '9' && pid < (1LL << 40))
            pid = pid * 10 + (name[i++] - '0');
        if (i == prefix || i >= name.size() || name[i] != '-' || pid <= 0) continue;
        if (pid == ::getpid()) continue;
        if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // alive
        stale.push_back(dir + "/" + name);
    }
    ::closedir(d);
    for (const std::string& p : stale) {
        std::error_code ec;
        std::filesystem::remove_all(p, ec);
    }
}

std::FILE* unlinked_temporary(const std::string& near_path, const std::string& what) {
    remove_stale_temporaries(folder_of(near_path));
    std::string name = temp_template(near_path);
    const int fd = ::mkstemp(name.data());
    if (fd < 0) throw OutputError("cannot write " + what + ": " + std::strerror(errno));
    ::unlink(name.c_str());
    std::FILE* f = ::fdopen(fd, "w+b");
    if (!f) {
        ::close(fd);
        throw OutputError("cannot write " + what + ": " + std::strerror(errno));
    }
    return f;
}

// --- AtomicFile

AtomicFile::AtomicFile(std::string target) : target_(std::move(target)) {
    // A symbolic link is followed: the file it names is replaced, the link stays a link.
    struct stat st {};
    if (::lstat(target_.c_str(), &st) == 0 && S_ISLNK(st.st_mode)) {
        std::error_code ec;
        const std::filesystem::path real = std::filesystem::weakly_canonical(target_, ec);
        if (!ec) target_ = real.string();
    }
    need_regular_or_absent(target_);
    remove_stale_temporaries(folder_of(target_));
    std::string name = temp_template(target_);
    const int fd = ::mkstemp(name.data());
    if (fd < 0) throw OutputError("cannot write " + target_ + ": " + std::strerror(errno));
    temp_ = name;
    slot_ = claim(temp_, false);
    ::fchmod(fd, 0666 & ~g_umask);  // mkstemp's 0600 would surprise on a shared printer host
    file_ = ::fdopen(fd, "wb");
    if (!file_) {
        const int err = errno;
        ::close(fd);
        ::unlink(temp_.c_str());
        release(slot_);
        throw OutputError("cannot write " + target_ + ": " + std::strerror(err));
    }
    std::setvbuf(file_, nullptr, _IOFBF, 1 << 16);
}

AtomicFile::~AtomicFile() {
    if (file_) std::fclose(file_);
    if (!committed_) ::unlink(temp_.c_str());
    release(slot_);
}

std::FILE* AtomicFile::stream() {
    return file_;
}

void AtomicFile::fail(const std::string& why) {
    throw OutputError("cannot write " + target_ + ": " + why);
}

void AtomicFile::write(std::string_view data) {
    if (!file_) fail("already closed");
    if (!data.empty() && std::fwrite(data.data(), 1, data.size(), file_) != data.size())
        fail(std::strerror(errno));
}

void AtomicFile::close() {
    if (!file_) return;
    std::FILE* f = file_;
    file_ = nullptr;
    const bool flushed = std::fflush(f) == 0 && !std::ferror(f);
    const int flush_err = errno;
    // EINVAL: a file system without fsync (some FUSE mounts); the data is written all the same.
    const bool synced = flushed && (::fsync(fileno(f)) == 0 || errno == EINVAL);
    const int sync_err = errno;
    const bool closed = std::fclose(f) == 0;
    if (!flushed) fail(std::strerror(flush_err ? flush_err : EIO));
    if (!synced) fail(std::strerror(sync_err));
    if (!closed) fail(std::strerror(errno));
}

void AtomicFile::commit() {
    if (committed_) return;
    close();
    need_regular_or_absent(target_);  // checked again: it may have appeared meanwhile
    if (std::rename(temp_.c_str(), target_.c_str()) != 0) fail(std::strerror(errno));
    committed_ = true;
    release(slot_);
    slot_ = -1;
    sync_folder(folder_of(target_));
}

// --- AtomicDir

AtomicDir::AtomicDir(std::string target) : target_(std::move(target)) {
    while (target_.size() > 1 && target_.back() == '/') target_.pop_back();
    struct stat st {};
    if (::stat(target_.c_str(), &st) == 0 && !S_ISDIR(st.st_mode))
        throw OutputError("cannot write into " + target_ + ": it exists and is not a folder");
    const std::string parent = folder_of(target_);
    remove_stale_temporaries(parent);
    std::string name = temp_template(target_);
    if (!::mkdtemp(name.data()))
        throw OutputError("cannot create the folder " + target_ + ": " + std::strerror(errno));
    ::chmod(name.c_str(), 0777 & ~g_umask);  // as mkdir would make it
    temp_ = name;
    slot_ = claim(temp_, true);
}

AtomicDir::~AtomicDir() {
    if (!committed_) {
        std::error_code ec;
        std::filesystem::remove_all(temp_, ec);
    }
    release(slot_);
}

void AtomicDir::commit() {
    if (committed_) return;
    namespace fs = std::filesystem;
    std::error_code ec;
    // A target that does not exist yet: the whole folder in one rename.
    if (!fs::exists(target_, ec) && std::rename(temp_.c_str(), target_.c_str()) == 0) {
        committed_ = true;
    } else {
        fs::create_directories(target_, ec);
        if (!fs::is_directory(target_))
            throw OutputError("cannot create the folder " + target_ + ": " + ec.message());
        for (const fs::directory_entry& e : fs::directory_iterator(temp_)) {
            const fs::path to = fs::path(target_) / e.path().filename();
            struct stat st {};
            if (::lstat(to.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
                throw OutputError("refusing to replace " + to.string() +
                                  ": it exists and is not a regular file");
            if (std::rename(e.path().c_str(), to.c_str()) != 0)
                throw OutputError("cannot write " + to.string() + ": " + std::strerror(errno));
        }
        fs::remove(temp_, ec);
        committed_ = true;
    }
    release(slot_);
    slot_ = -1;
    sync_folder(target_);
}

// --- OutputGroup

void OutputGroup::commit_all() {
    for (auto& p : pending_) p->commit();
    pending_.clear();
}

void OutputGroup::hand_over(OutputGroup& other) {
    for (auto& p : pending_) other.pending_.push_back(std::move(p));
    pending_.clear();
}

void write_file_atomically(const std::string& path, std::string_view text, OutputGroup* group) {
    auto file = std::make_unique<AtomicFile>(path);
    file->write(text);
    file->close();
    if (group)
        group->hold(std::move(file));
    else
        file->commit();
}

}  // namespace carve
