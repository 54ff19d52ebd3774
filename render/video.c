/* video.c -- MP4 through a pipe to ffmpeg.
 *
 * ffmpeg runs as a child (fork + execvp, no shell) reading raw RGBA frames
 * on its stdin and writing H.264 yuv420p MP4 to PATH.tmpPID; close waits for
 * it, checks its exit status and renames the temporary to PATH, so PATH
 * exists only as a finished video. The command:
 *
 *   ffmpeg -nostdin -loglevel error -y -f rawvideo -pix_fmt rgba -s WxH
 *          -framerate FPS -i pipe:0 -vf pad=ceil(iw/2)*2:ceil(ih/2)*2
 *          -c:v libx264 -preset ultrafast -crf 23 -pix_fmt yuv420p
 *          -movflags +faststart -f mp4 PATH.tmpPID
 *
 * yuv420p halves the chroma, so a side must be even: the pad filter adds a
 * black column or row to an odd side. -preset ultrafast -crf 23: the video
 * is written beside the renderer (and, live, beside the flight loop) on 2
 * cores, so the encoder's CPU time per frame matters more than the file's
 * size. A manual run on the development machine (ffmpeg 5.1, libx264),
 *   ffmpeg -f lavfi -i testsrc2=size=1280x720:rate=30 -frames:v 300
 *          -c:v libx264 -preset P -crf 23 -pix_fmt yuv420p -f mp4 out.mp4
 * encoded 300 frames in 0.76 s at 1.3 cores with ultrafast, 1.3 s at 1.6
 * cores with superfast, 1.6 s at 1.8 cores with veryfast: ultrafast costs
 * about 3 ms of CPU a frame against 10 ms for veryfast, for a file about
 * 2.8x larger (flat-shaded deck views compress far better than testsrc2).
 *
 * ffmpeg's stderr goes to an unlinked temporary file (nothing is left
 * behind, even after a crash); its last lines go into the error when it
 * fails. A frame is one write (a loop only for a partial write). A write to
 * an ffmpeg that has died raises SIGPIPE, which by default kills the
 * process: the writing thread blocks SIGPIPE around the write and consumes
 * a SIGPIPE it raised (sigtimedwait with a zero timeout), so EPIPE becomes
 * an error naming the file and the process-wide disposition is untouched.
 * Every descriptor is opened close-on-exec, so a second video's ffmpeg
 * does not inherit the first one's pipe (which would keep the first from
 * ever seeing the end of its input).
 */
#define _GNU_SOURCE
#include "render_priv.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

struct render_video {
    pid_t pid;          /* ffmpeg; 0 once reaped */
    int fd;             /* the pipe to its stdin; -1 once closed */
    int log_fd;         /* its stderr (unlinked file) */
    int w, h;
    long frames;
    int failed;         /* a frame failed: close reports it and removes the temporary */
    char *path, *tmp;
};

/* The last lines of ffmpeg's stderr (at most cap - 1 bytes, newlines as
 * "; "), or "" if it said nothing. */
static void log_tail(int fd, char *out, size_t cap)
{
    out[0] = '\0';
    if (fd < 0 || cap < 2)
        return;
    struct stat st;
    if (fstat(fd, &st) != 0 || st.st_size <= 0)
        return;
    char buf[600];
    size_t want = sizeof buf - 1 < cap - 1 ? sizeof buf - 1 : cap - 1;
    off_t off = st.st_size > (off_t)want ? st.st_size - (off_t)want : 0;
    ssize_t n = pread(fd, buf, want, off);
    if (n <= 0)
        return;
    buf[n] = '\0';
    char *s = buf;
    if (off > 0) { /* start at a whole line */
        char *nl = strchr(s, '\n');
        if (nl && nl[1])
            s = nl + 1;
    }
    size_t len = strlen(s);
    while (len > 0 && (s[len - 1] == '\n' || s[len - 1] == '\r' || s[len - 1] == ' '))
        s[--len] = '\0';
    size_t j = 0;
    for (size_t i = 0; s[i] && j + 3 < cap; i++) {
        if (s[i] == '\n') {
            out[j++] = ';';
            out[j++] = ' ';
        } else if (s[i] != '\r') {
            out[j++] = s[i];
        }
    }
    out[j] = '\0';
}

/* Run argv with stdin/stdout/stderr from in_fd/out_fd/err_fd (-1: /dev/null);
 * returns the pid, or -1 with errno (exec failures included: the child
 * reports its errno through a close-on-exec pipe). */
static pid_t spawn(char *const argv[], int in_fd, int out_fd, int err_fd)
{
    int st[2];
    if (pipe2(st, O_CLOEXEC) != 0)
        return -1;
    int null_fd = open("/dev/null", O_RDWR | O_CLOEXEC);
    if (null_fd < 0) {
        int e = errno;
        close(st[0]);
        close(st[1]);
        errno = e;
        return -1;
    }
    pid_t pid = fork();
    if (pid == 0) {
        /* The child: only async-signal-safe calls until exec. */
        sigset_t none;
        sigemptyset(&none);
        sigprocmask(SIG_SETMASK, &none, NULL);
        signal(SIGPIPE, SIG_DFL);
        int fds[3] = {in_fd >= 0 ? in_fd : null_fd, out_fd >= 0 ? out_fd : null_fd,
                      err_fd >= 0 ? err_fd : null_fd};
        for (int i = 0; i < 3; i++)
            if (dup2(fds[i], i) < 0)
                goto fail;
        execvp(argv[0], argv);
    fail:;
        int e = errno;
        ssize_t unused = write(st[1], &e, sizeof e);
        (void)unused;
        _exit(127);
    }
    int e = errno;
    close(st[1]);
    close(null_fd);
    if (pid < 0) {
        close(st[0]);
        errno = e;
        return -1;
    }
    int child_errno = 0;
    ssize_t n;
    do
        n = read(st[0], &child_errno, sizeof child_errno);
    while (n < 0 && errno == EINTR);
    close(st[0]);
    if (n == (ssize_t)sizeof child_errno) {
        int status;
        while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
            ;
        errno = child_errno;
        return -1;
    }
    return pid;
}

static int wait_child(pid_t pid, int *status)
{
    pid_t r;
    do
        r = waitpid(pid, status, 0);
    while (r < 0 && errno == EINTR);
    return r == pid ? 0 : -1;
}

static void describe_status(int status, char *out, size_t cap)
{
    if (WIFEXITED(status))
        snprintf(out, cap, "exited with status %d", WEXITSTATUS(status));
    else if (WIFSIGNALED(status))
        snprintf(out, cap, "was killed by signal %d", WTERMSIG(status));
    else
        snprintf(out, cap, "stopped (status %d)", status);
}

int render_video_available(void)
{
    int p[2];
    if (pipe2(p, O_CLOEXEC) != 0)
        return 0;
    char *argv[] = {"ffmpeg", "-hide_banner", "-nostdin", "-encoders", NULL};
    pid_t pid = spawn(argv, -1, p[1], -1);
    close(p[1]);
    if (pid < 0) {
        close(p[0]);
        return 0;
    }
    /* The list is a few tens of kB: read it all (ffmpeg would block on a
     * full pipe), keeping a window that a line cannot straddle unseen. */
    char buf[8192 + 64];
    size_t keep = 0;
    int found = 0;
    for (;;) {
        ssize_t n = read(p[0], buf + keep, sizeof buf - 1 - keep);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            break;
        size_t len = keep + (size_t)n;
        buf[len] = '\0';
        if (strstr(buf, " libx264 "))
            found = 1;
        keep = len < 63 ? len : 63;
        memmove(buf, buf + len - keep, keep);
    }
    close(p[0]);
    int status;
    if (wait_child(pid, &status) != 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return 0;
    return found;
}

static void video_free(render_video *v)
{
    if (!v)
        return;
    if (v->fd >= 0)
        close(v->fd);
    if (v->log_fd >= 0)
        close(v->log_fd);
    free(v->path);
    free(v->tmp);
    free(v);
}

render_video *render_video_open(const char *path, int width, int height, double fps, core_err *err)
{
    if (!path || !path[0]) {
        core_err_set(err, -1, "render: video: expected an output path");
        return NULL;
    }
    if (width < 2 || height < 2 || width > RENDER_SIZE_MAX || height > RENDER_SIZE_MAX) {
        core_err_set(err, -1, "render: video %s: size %dx%d: expected 2 to %d pixels a side", path, width,
                     height, RENDER_SIZE_MAX);
        return NULL;
    }
    if (!(fps > 0.0 && fps <= 1000.0)) {
        core_err_set(err, -1, "render: video %s: fps = %g: expected more than 0 and at most 1000", path, fps);
        return NULL;
    }
    render_video *v = calloc(1, sizeof *v);
    if (!v) {
        core_err_set(err, -1, "render: video %s: out of memory", path);
        return NULL;
    }
    v->fd = -1;
    v->log_fd = -1;
    v->w = width;
    v->h = height;
    size_t n = strlen(path) + 32;
    v->path = strdup(path);
    v->tmp = malloc(n);
    if (!v->path || !v->tmp) {
        video_free(v);
        core_err_set(err, -1, "render: video %s: out of memory", path);
        return NULL;
    }
    snprintf(v->tmp, n, "%s.tmp%ld", path, (long)getpid());

    /* Create the temporary here: a missing directory or a read-only one is
     * an error naming the file now, not an ffmpeg message at close. */
    int tfd = open(v->tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (tfd < 0) {
        core_err_set(err, -1, "render: video %s: cannot create %s: %s", path, v->tmp, strerror(errno));
        video_free(v);
        return NULL;
    }
    close(tfd);

    const char *tmpdir = getenv("TMPDIR");
    char logname[PATH_MAX];
    snprintf(logname, sizeof logname, "%s/disim-ffmpeg-XXXXXX", tmpdir && tmpdir[0] ? tmpdir : "/tmp");
    v->log_fd = mkostemp(logname, O_CLOEXEC);
    if (v->log_fd < 0) {
        core_err_set(err, -1, "render: video %s: cannot create ffmpeg's log %s: %s", path, logname,
                     strerror(errno));
        unlink(v->tmp);
        video_free(v);
        return NULL;
    }
    unlink(logname);

    int p[2];
    if (pipe2(p, O_CLOEXEC) != 0) {
        core_err_set(err, -1, "render: video %s: pipe: %s", path, strerror(errno));
        unlink(v->tmp);
        video_free(v);
        return NULL;
    }
    /* A larger pipe takes a whole small frame at once and cuts the context
     * switches for a large one; the default size works too. */
    (void)fcntl(p[1], F_SETPIPE_SZ, 1 << 20);

    char size[32], rate[32];
    snprintf(size, sizeof size, "%dx%d", width, height);
    snprintf(rate, sizeof rate, "%.9g", fps);
    char *argv[] = {"ffmpeg", "-nostdin", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgba",
                    "-s", size, "-framerate", rate, "-i", "pipe:0", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                    "-c:v", "libx264", "-preset", "ultrafast", "-crf", "23", "-pix_fmt", "yuv420p",
                    "-movflags", "+faststart", "-f", "mp4", v->tmp, NULL};
    v->pid = spawn(argv, p[0], -1, v->log_fd);
    int e = errno;
    close(p[0]);
    if (v->pid < 0) {
        close(p[1]);
        core_err_set(err, -1, "render: video %s: cannot run ffmpeg: %s", path, strerror(e));
        unlink(v->tmp);
        video_free(v);
        return NULL;
    }
    v->fd = p[1];
    return v;
}

/* Write all of buf to fd with SIGPIPE blocked in this thread; a SIGPIPE the
 * write raised is consumed before the mask is restored (one already pending
 * before is left alone). 0, or -1 with errno. */
static int write_nosigpipe(int fd, const uint8_t *buf, size_t n)
{
    sigset_t pipe_set, old;
    sigemptyset(&pipe_set);
    sigaddset(&pipe_set, SIGPIPE);
    pthread_sigmask(SIG_BLOCK, &pipe_set, &old);
    sigset_t pending;
    sigemptyset(&pending);
    sigpending(&pending);
    int was_pending = sigismember(&pending, SIGPIPE);
    int rc = 0, e = 0;
    size_t done = 0;
    while (done < n) {
        ssize_t k = write(fd, buf + done, n - done);
        if (k < 0) {
            if (errno == EINTR)
                continue;
            rc = -1;
            e = errno;
            break;
        }
        done += (size_t)k;
    }
    if (rc != 0 && e == EPIPE && !was_pending) {
        const struct timespec zero = {0, 0};
        while (sigtimedwait(&pipe_set, NULL, &zero) < 0 && errno == EINTR)
            ;
    }
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    errno = e;
    return rc;
}

int render_video_frame(render_video *v, const uint8_t *rgba, core_err *err)
{
    if (!v || !rgba)
        return core_err_set(err, -1, "render: video: no video or no frame");
    if (v->failed || v->fd < 0)
        return core_err_set(err, -1, "render: video %s: an earlier frame failed", v->path);
    if (write_nosigpipe(v->fd, rgba, (size_t)4 * v->w * v->h) == 0) {
        v->frames++;
        return 0;
    }
    int e = errno;
    v->failed = 1;
    close(v->fd);
    v->fd = -1;
    char why[64] = "", tail[400];
    int status;
    if (e == EPIPE && wait_child(v->pid, &status) == 0) {
        v->pid = 0;
        describe_status(status, why, sizeof why);
    }
    log_tail(v->log_fd, tail, sizeof tail);
    if (e == EPIPE)
        return core_err_set(err, -1, "render: video %s: ffmpeg stopped reading frames%s%s%s%s%s", v->path,
                            why[0] ? " (it " : "", why, why[0] ? ")" : "", tail[0] ? ": " : "", tail);
    return core_err_set(err, -1, "render: video %s: writing frame %ld to ffmpeg: %s%s%s", v->path, v->frames,
                        strerror(e), tail[0] ? "; ffmpeg: " : "", tail);
}

int render_video_close(render_video *v, core_err *err)
{
    if (!v)
        return core_err_set(err, -1, "render: video: no video to close");
    if (v->fd >= 0) {
        close(v->fd);
        v->fd = -1;
    }
    int status = 0, reaped = 0;
    if (v->pid > 0) {
        reaped = wait_child(v->pid, &status) == 0;
        v->pid = 0;
    }
    char tail[400];
    log_tail(v->log_fd, tail, sizeof tail);
    int rc = 0;
    if (v->failed) {
        rc = core_err_set(err, -1, "render: video %s: not written: a frame failed%s%s", v->path,
                          tail[0] ? "; ffmpeg: " : "", tail);
    } else if (reaped && !(WIFEXITED(status) && WEXITSTATUS(status) == 0)) {
        char why[64];
        describe_status(status, why, sizeof why);
        rc = core_err_set(err, -1, "render: video %s: ffmpeg %s%s%s", v->path, why, tail[0] ? ": " : "", tail);
    } else if (v->frames == 0) {
        rc = core_err_set(err, -1, "render: video %s: no frames were written", v->path);
    } else if (rename(v->tmp, v->path) != 0) {
        rc = core_err_set(err, -1, "render: video %s: cannot rename %s to it: %s", v->path, v->tmp,
                          strerror(errno));
    }
    if (rc != 0)
        unlink(v->tmp);
    video_free(v);
    return rc;
}

void render_video_abort(render_video *v)
{
    if (!v)
        return;
    if (v->fd >= 0) {
        close(v->fd);
        v->fd = -1;
    }
    if (v->pid > 0) {
        kill(v->pid, SIGKILL);
        int status;
        wait_child(v->pid, &status);
        v->pid = 0;
    }
    unlink(v->tmp);
    video_free(v);
}
