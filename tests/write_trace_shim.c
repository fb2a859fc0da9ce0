// An LD_PRELOAD library for the write-order test (tests/cli_write_order_test.cpp): records the
// calls by which a process creates files -- open/openat/fopen (with the path and whether for
// writing), write, fsync/fdatasync, rename/renameat, close -- one line each, appended to the file
// MESHTOUR_WRITE_TRACE names:
//   open FD W|R PATH       write FD       fsync FD       rename FROM\tTO       close FD
// Relative paths are made absolute against the working directory. With
// MESHTOUR_WRITE_TRACE_DROP_FSYNC=1 every fsync/fdatasync succeeds without doing anything or being
// recorded: a writer that skips the step, which the test must catch.
#define _GNU_SOURCE
#include <dlfcn.h>
#include <fcntl.h>
#include <limits.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/syscall.h>
#include <unistd.h>

static __thread int inside;  // the shim's own calls are not recorded
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;

static void record(const char* fmt, ...) {
  const char* file = getenv("MESHTOUR_WRITE_TRACE");
  if (!file || inside) return;
  inside = 1;
  char line[5 * PATH_MAX];
  va_list args;
  va_start(args, fmt);
  int n = vsnprintf(line, sizeof line - 1, fmt, args);
  va_end(args);
  if (n > (int)sizeof line - 2) n = (int)sizeof line - 2;
  line[n++] = '\n';
  pthread_mutex_lock(&lock);
  const int fd = (int)syscall(SYS_openat, AT_FDCWD, file, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd >= 0) {
    syscall(SYS_write, fd, line, (size_t)n);
    syscall(SYS_close, fd);
  }
  pthread_mutex_unlock(&lock);
  inside = 0;
}

static const char* absolute(const char* path, char* out) {
  if (!path) return "";
  if (path[0] == '/') return path;
  char cwd[PATH_MAX];
  if (!getcwd(cwd, sizeof cwd)) return path;
  snprintf(out, 2 * PATH_MAX, "%s/%s", cwd, path);
  return out;
}

static int drop_fsync(void) {
  const char* v = getenv("MESHTOUR_WRITE_TRACE_DROP_FSYNC");
  return v && strcmp(v, "1") == 0;
}

#define REAL(name) \
  static __typeof__(&name) real_##name; \
  if (!real_##name) real_##name = (__typeof__(&name))dlsym(RTLD_NEXT, #name)

static void record_open(int fd, int flags, const char* path) {
  if (fd < 0) return;
  char buf[2 * PATH_MAX];
  record("open %d %c %s", fd, (flags & (O_WRONLY | O_RDWR | O_CREAT)) ? 'W' : 'R', absolute(path, buf));
}

int open(const char* path, int flags, ...) {
  REAL(open);
  mode_t mode = 0;
  if (flags & (O_CREAT | O_TMPFILE)) { va_list a; va_start(a, flags); mode = va_arg(a, mode_t); va_end(a); }
  const int fd = real_open(path, flags, mode);
  record_open(fd, flags, path);
  return fd;
}
int open64(const char* path, int flags, ...) {
  REAL(open64);
  mode_t mode = 0;
  if (flags & (O_CREAT | O_TMPFILE)) { va_list a; va_start(a, flags); mode = va_arg(a, mode_t); va_end(a); }
  const int fd = real_open64(path, flags, mode);
  record_open(fd, flags, path);
  return fd;
}
int openat(int dir, const char* path, int flags, ...) {
  REAL(openat);
  mode_t mode = 0;
  if (flags & (O_CREAT | O_TMPFILE)) { va_list a; va_start(a, flags); mode = va_arg(a, mode_t); va_end(a); }
  const int fd = real_openat(dir, path, flags, mode);
  record_open(fd, flags, path);  // (meshtour's writers pass absolute or working-directory paths)
  return fd;
}
int openat64(int dir, const char* path, int flags, ...) {
  REAL(openat64);
  mode_t mode = 0;
  if (flags & (O_CREAT | O_TMPFILE)) { va_list a; va_start(a, flags); mode = va_arg(a, mode_t); va_end(a); }
  const int fd = real_openat64(dir, path, flags, mode);
  record_open(fd, flags, path);
  return fd;
}

static void record_fopen(FILE* f, const char* path, const char* mode) {
  if (!f) return;
  char buf[2 * PATH_MAX];
  const int writing = strchr(mode, 'w') || strchr(mode, 'a') || strchr(mode, '+');
  record("open %d %c %s", fileno(f), writing ? 'W' : 'R', absolute(path, buf));
}
FILE* fopen(const char* path, const char* mode) {
  REAL(fopen);
  FILE* f = real_fopen(path, mode);
  record_fopen(f, path, mode);
  return f;
}
FILE* fopen64(const char* path, const char* mode) {
  REAL(fopen64);
  FILE* f = real_fopen64(path, mode);
  record_fopen(f, path, mode);
  return f;
}

ssize_t write(int fd, const void* data, size_t size) {
  REAL(write);
  const ssize_t n = real_write(fd, data, size);
  if (n > 0 && fd > 2) record("write %d", fd);
  return n;
}

int fsync(int fd) {
  REAL(fsync);
  if (drop_fsync()) return 0;
  const int r = real_fsync(fd);
  if (r == 0) record("fsync %d", fd);
  return r;
}
int fdatasync(int fd) {
  REAL(fdatasync);
  if (drop_fsync()) return 0;
  const int r = real_fdatasync(fd);
  if (r == 0) record("fsync %d", fd);
  return r;
}

int rename(const char* from, const char* to) {
  REAL(rename);
  const int r = real_rename(from, to);
  char a[2 * PATH_MAX], b[2 * PATH_MAX];
  if (r == 0) record("rename %s\t%s", absolute(from, a), absolute(to, b));
  return r;
}
int renameat(int from_dir, const char* from, int to_dir, const char* to) {
  REAL(renameat);
  const int r = real_renameat(from_dir, from, to_dir, to);
  char a[2 * PATH_MAX], b[2 * PATH_MAX];
  if (r == 0) record("rename %s\t%s", absolute(from, a), absolute(to, b));
  return r;
}
int renameat2(int from_dir, const char* from, int to_dir, const char* to, unsigned flags) {
  REAL(renameat2);
  const int r = real_renameat2(from_dir, from, to_dir, to, flags);
  char a[2 * PATH_MAX], b[2 * PATH_MAX];
  if (r == 0) record("rename %s\t%s", absolute(from, a), absolute(to, b));
  return r;
}

int close(int fd) {
  REAL(close);
  if (fd > 2) record("close %d", fd);
  return real_close(fd);
}
