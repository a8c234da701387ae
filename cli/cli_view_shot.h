/* cli_view_shot.h - pictures of a `pomlab view` page: headless Chromium for
 * screenshots, ffmpeg for films (docs/view.md section 5). CLI code: the
 * functions print why they fail ("pomlab view: ...") and return 1. */
#ifndef POM_CLI_VIEW_SHOT_H
#define POM_CLI_VIEW_SHOT_H

#include <stddef.h>

/* The first of names (NULL-terminated) found in PATH, or names[k] itself
 * when it holds a slash, into buf; 0 when found, -1 otherwise. */
int pom_view_find_program(const char *const *names, char *buf, size_t cap);

/* $POM_CHROMIUM when set, else chromium, chromium-browser or google-chrome
 * in PATH; 0 when found. */
int pom_view_find_chromium(char *buf, size_t cap);

/* Opens url (file://...) in headless Chromium with software WebGL, w x h
 * pixels, and writes its screenshot to png (an absolute path); scratch files
 * go to tmpdir. 0 when the page finished drawing without a script error;
 * else prints why, naming `what`, and returns 1. */
int pom_view_screenshot(const char *chromium, const char *url, const char *png, int w, int h,
                        const char *tmpdir, const char *what);

/* The film of the n_frames frames of the page html (absolute path) into mp4
 * (absolute path): w x h frames at fps, drawn by Chromium in tiled batches
 * (#tiles=...) and cut and encoded by ffmpeg (untile, libx264). 0 ok, else 1
 * after printing why. */
int pom_view_mp4(const char *chromium, const char *ffmpeg, const char *html, const char *mp4,
                 int n_frames, int w, int h, int fps, const char *tmpdir);

/* path made absolute (realpath: it must exist), and an output path made
 * absolute through its folder (the file need not exist); 0 ok, -1 with
 * errno set. */
int pom_view_abs_path(const char *path, char *buf, size_t cap);
int pom_view_abs_output(const char *path, char *buf, size_t cap);

/* Removes the scratch files of pom_view_screenshot and pom_view_mp4 (at most
 * `batches` film batches) and the folder dir. */
void pom_view_remove_tmpdir(const char *dir, int batches);

#endif
