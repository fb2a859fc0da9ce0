// The soak test's fault injector (scripts/soak.py), an LD_PRELOAD library. In a meshtour process it
//  - fails chosen calls on files under MESHTOUR_FAULT_DIR: write/fwrite with ENOSPC while the file
//    MESHTOUR_FAULT_DISK_FULL exists (a full disk, for a window the driver opens and closes), and
//    write, fwrite, fsync and rename with EIO at the rates MESHTOUR_FAULT_P_WRITE, _P_FSYNC and
//    _P_RENAME (per call, 0..1);
//  - kills the process inside a chosen stage, as a farm's time limit does: when the program
//    announces a stage ({"event":"stage","stage":"S"} on stderr, tour/progress.h) and
//    MESHTOUR_FAULT_KILL lists "S:P", then with probability P a thread waits a random time up to
//    MESHTOUR_FAULT_KILL_DELAY_MS, sends SIGTERM, and sends SIGKILL MESHTOUR_FAULT_GRACE_MS later
//    if the process is still there (a grace of 0 = SIGKILL at once);
//  - records, one line each in MESHTOUR_FAULT_LOG ("<ns since epoch> <pid> <event> ..."):
//    start ITEM (the batch begins to make an item), stage S, fault KIND PATH, kill S SIGNAL, and
//    rename TO for every file renamed into place under the folder (a finished output).
// MESHTOUR_FAULT_SEED makes the choices repeatable per process (mixed with the pid).
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <pthread.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#define MAX_FD 4096

static __thread int inside;
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static char watched[MAX_FD];  // fd -> opened for writing under MESHTOUR_FAULT_DIR
static uint64_t rng_state;

static uint64_t next_random(void) {  // xorshift64*, under `lock`
  if (!rng_state) {
    const char* seed = getenv("MESHTOUR_FAULT_SEED");
    rng_state = ((seed ? strtoull(seed, NULL, 10) : 1) * 0x9E3779B97F4A7C15ull) ^ ((uint64_t)getpid() << 17) ^ 0x2545F4914F6CDD1Dull;
  }
  rng_state ^= rng_state >> 12;
  rng_state ^= rng_state << 25;
  rng_state ^= rng_state >> 27;
  return rng_state * 0x2545F4914F6CDD1Dull;
}

static double uniform(void) {
  pthread_mutex_lock(&lock);
  const double u = (double)(next_random() >> 11) / 9007199254740992.0;
  pthread_mutex_unlock(&lock);
  return u;
}

static double env_double(const char* name) {
  const char* v = getenv(name);
  return v ? atof(v) : 0.0;
}

static void record(const char* fmt, ...) {
  const char* file = getenv("MESHTOUR_FAULT_LOG");
  if (!file) return;
  char line[3 * PATH_MAX];
  struct timespec now;
  clock_gettime(CLOCK_REALTIME, &now);
  int n = snprintf(line, sizeof line, "%lld %d ", (long long)now.tv_sec * 1000000000ll + now.tv_nsec, (int)getpid());
  va_list args;
  va_start(args, fmt);
  n += vsnprintf(line + n, sizeof line - (size_t)n - 1, fmt, args);
  va_end(args);
  if (n > (int)sizeof line - 2) n = (int)sizeof line - 2;
  line[n++] = '\n';
  const int fd = (int)syscall(SYS_openat, AT_FDCWD, file, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd >= 0) {
    syscall(SYS_write, fd, line, (size_t)n);
    syscall(SYS_close, fd);
  }
}

// Whether `path` (absolute or relative to the working directory) lies under MESHTOUR_FAULT_DIR.
static int under_dir(const char* path) {
  const char* dir = getenv("MESHTOUR_FAULT_DIR");
  if (!dir || !path) return 0;
  char full[2 * PATH_MAX];
  if (path[0] != '/') {
    char cwd[PATH_MAX];
    if (!getcwd(cwd, sizeof cwd)) return 0;
    snprintf(full, sizeof full, "%s/%s", cwd, path);
    path = full;
  }
  const size_t n = strlen(dir);
  return strncmp(path, dir, n) == 0 && (path[n] == '/' || path[n] == 0);
}

static int disk_full(void) {
  const char* flag = getenv("MESHTOUR_FAULT_DISK_FULL");
  struct stat st;
  return flag && syscall(SYS_newfstatat, AT_FDCWD, flag, &st, 0) == 0;
}

// The fault for a write to a watched file: ENOSPC while the disk is "full", EIO at its rate.
static int write_fault(int fd, const char* call) {
  if (fd < 0 || fd >= MAX_FD || !watched[fd] || inside) return 0;
  inside = 1;
  int error = 0;
  if (disk_full()) {
    error = ENOSPC;
    record("fault disk-full %s fd %d", call, fd);
  } else if (uniform() < env_double("MESHTOUR_FAULT_P_WRITE")) {
    error = EIO;
    record("fault write %s fd %d", call, fd);
  }
  inside = 0;
  return error;
}

#define REAL(name) \
  static __typeof__(&name) real_##name; \
  if (!real_##name) real_##name = (__typeof__(&name))dlsym(RTLD_NEXT, #name)

static void opened(int fd, int flags, const char* path) {
  if (fd < 0 || fd >= MAX_FD) return;
  watched[fd] = (flags & (O_WRONLY | O_RDWR)) && under_dir(path);
}

int open(const char* path, int flags, ...) {
  REAL(open);
  va_list a;
  va_start(a, flags);
  const int fd = real_open(path, flags, va_arg(a, int));
  va_end(a);
  opened(fd, flags, path);
  return fd;
}
int open64(const char* path, int flags, ...) {
  REAL(open64);
  va_list a;
  va_start(a, flags);
  const int fd = real_open64(path, flags, va_arg(a, int));
  va_end(a);
  opened(fd, flags, path);
  return fd;
}
int openat(int dir, const char* path, int flags, ...) {
  REAL(openat);
  va_list a;
  va_start(a, flags);
  const int fd = real_openat(dir, path, flags, va_arg(a, int));
  va_end(a);
  opened(fd, flags, path);
  return fd;
}

static void fopened(FILE* f, const char* path, const char* mode) {
  if (f) opened(fileno(f), strpbrk(mode, "wa+") ? O_WRONLY : O_RDONLY, path);
}
FILE* fopen(const char* path, const char* mode) {
  REAL(fopen);
  FILE* f = real_fopen(path, mode);
  fopened(f, path, mode);
  return f;
}
FILE* fopen64(const char* path, const char* mode) {
  REAL(fopen64);
  FILE* f = real_fopen64(path, mode);
  fopened(f, path, mode);
  return f;
}

ssize_t write(int fd, const void* data, size_t size) {
  REAL(write);
  const int error = write_fault(fd, "write");
  if (error) {
    errno = error;
    return -1;
  }
  return real_write(fd, data, size);
}

size_t fwrite(const void* data, size_t size, size_t count, FILE* f) {
  REAL(fwrite);
  const int error = write_fault(fileno(f), "fwrite");
  if (error) {
    errno = error;
    return 0;
  }
  return real_fwrite(data, size, count, f);
}

static int sync_fault(int fd) {
  if (fd < 0 || fd >= MAX_FD || inside) return 0;
  // A directory's fsync (after a rename) is not watched by open's flags: check the rate for it too.
  if (!watched[fd]) {
    char link[64], path[PATH_MAX];
    snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
    const ssize_t n = readlink(link, path, sizeof path - 1);
    if (n <= 0) return 0;
    path[n] = 0;
    if (!under_dir(path)) return 0;
  }
  if (uniform() >= env_double("MESHTOUR_FAULT_P_FSYNC")) return 0;
  record("fault fsync fd %d", fd);
  return EIO;
}
int fsync(int fd) {
  REAL(fsync);
  const int error = sync_fault(fd);
  if (error) {
    errno = error;
    return -1;
  }
  return real_fsync(fd);
}
int fdatasync(int fd) {
  REAL(fdatasync);
  const int error = sync_fault(fd);
  if (error) {
    errno = error;
    return -1;
  }
  return real_fdatasync(fd);
}

int rename(const char* from, const char* to) {
  REAL(rename);
  if (under_dir(to) && uniform() < env_double("MESHTOUR_FAULT_P_RENAME")) {
    record("fault rename %s", to);
    errno = EIO;
    return -1;
  }
  const int result = real_rename(from, to);
  if (result == 0 && under_dir(to)) record("rename %s", to);
  return result;
}

int close(int fd) {
  REAL(close);
  if (fd >= 0 && fd < MAX_FD) watched[fd] = 0;
  return real_close(fd);
}

// Kills: a thread waits, then SIGTERM (the program's handler starts its orderly stop), then SIGKILL
// after the grace if the process has not ended.
static volatile int kill_planned;
static char current_stage[64] = "start";  // the last stage announced: where a signal lands

static void* killer(void* arg) {
  (void)arg;
  const double delay_ms = env_double("MESHTOUR_FAULT_KILL_DELAY_MS") * uniform();
  const double grace_ms = env_double("MESHTOUR_FAULT_GRACE_MS");
  struct timespec wait = {(time_t)(delay_ms / 1000), (long)(((long long)(delay_ms * 1e6)) % 1000000000ll)};
  nanosleep(&wait, NULL);
  if (grace_ms > 0) {
    record("kill %s TERM", current_stage);
    kill(getpid(), SIGTERM);
    struct timespec grace = {(time_t)(grace_ms / 1000), (long)(((long long)(grace_ms * 1e6)) % 1000000000ll)};
    nanosleep(&grace, NULL);
    record("kill %s KILL-after-grace", current_stage);
  } else {
    record("kill %s KILL", current_stage);
  }
  kill(getpid(), SIGKILL);
  return NULL;
}

// What the program prints on stderr: the stage announcements and the batch's item lines.
static void saw_text(const char* text) {
  const char* s = strstr(text, "\"event\":\"stage\",\"stage\":\"");
  if (s) {
    s += strlen("\"event\":\"stage\",\"stage\":\"");
    char stage[64];
    size_t n = 0;
    while (s[n] && s[n] != '"' && n < sizeof stage - 1) stage[n] = s[n], n++;
    stage[n] = 0;
    snprintf(current_stage, sizeof current_stage, "%s", stage);
    record("stage %s", stage);
    const char* plan = getenv("MESHTOUR_FAULT_KILL");  // "load:0.1,render:0.05,..."
    if (plan && !kill_planned) {
      char key[80];
      snprintf(key, sizeof key, "%s:", stage);
      const char* at = strstr(plan, key);
      if (at && (at == plan || at[-1] == ',') && uniform() < atof(at + strlen(key))) {
        kill_planned = 1;
        pthread_t t;
        if (pthread_create(&t, NULL, killer, NULL) == 0) pthread_detach(t);
      }
    }
  }
  const char* item = strstr(text, "== item ");
  if (item && strstr(item, " -> ")) record("start %d", atoi(item + strlen("== item ")));
}

int fprintf(FILE* f, const char* fmt, ...) {
  char text[1024];
  va_list a;
  va_start(a, fmt);
  vsnprintf(text, sizeof text, fmt, a);
  va_end(a);
  if (f == stderr && !inside) {
    inside = 1;
    saw_text(text);
    inside = 0;
  }
  va_start(a, fmt);
  const int n = vfprintf(f, fmt, a);
  va_end(a);
  return n;
}
