/*
 * page.h — the study's page (brdfkit report) and what goes into it: the
 * sections the other commands write, checked before they are copied in,
 * links escaped where they are written, and input files read with a bound.
 */
#ifndef ANALYSIS_PAGE_H
#define ANALYSIS_PAGE_H

#include <stddef.h>
#include <stdio.h>

/* A section is a page fragment of tables and an inline plot: the largest
 * brdfkit writes is about 31 KB (results/compare/env), so 4 MiB is over a
 * hundred times what one needs and still nothing a page should inline. */
#define BK_PAGE_SECTION_MAX ((size_t)4 << 20)

/* The whole of path ("-": standard input), at most cap bytes. A regular
 * file larger than cap is refused from its size before a byte is read;
 * anything else (a FIFO, a device such as /dev/zero, a terminal) is read
 * until its end or cap + 1 bytes, so no input can take more than cap + 1
 * bytes of memory. Returns the text (malloc'd, NUL-terminated, *len its
 * length), or NULL with err: "cannot be read: REASON", "is a directory",
 * "is N bytes, more than C", "is longer than C bytes". */
char *bk_read_bounded(const char *path, size_t cap, size_t *len, char *err, size_t errlen);
/* The same for a file brdfkit wrote (report's sections): a path other than
 * "-" must be a regular file, else err "is a directory" or "not a regular
 * file (a FIFO)", found without blocking on the open (bk_in_open). */
char *bk_read_regular(const char *path, size_t cap, size_t *len, char *err, size_t errlen);

/* s escaped as bk_html_text writes it (& < > "), malloc'd; NULL when out of
 * memory. For a link prefix a section writer pastes into many attributes. */
char *bk_html_escaped(const char *s);

/* A section as brdfkit writes it, checked before the page takes it in:
 *   - the marker: it opens with <section id="ID"> on its first line (ID made
 *     of letters, digits, '-' and '_') and ends with </section>;
 *   - nothing that runs: only the elements and attributes brdfkit writes
 *     (tables, text, links, images, inline SVG plots and their <style>),
 *     every attribute value quoted, links and images relative or http(s)
 *     (no javascript:, data: or any other scheme, no character reference
 *     that could spell one), a <style> of plain selectors and properties (no
 *     url(), expression or @import), every '<' of text escaped, no comment.
 * So no <script>, no on* handler, no <iframe>, <object>, <embed>, <base>,
 * <meta>, <form> and no text that ends a tag early. Returns 0 with the id
 * in id (idlen bytes), or -1 with err naming the first offence and its line. */
int bk_section_check(const char *text, size_t len, char *id, size_t idlen, char *err, size_t errlen);

/* The section text[0..len) (one that passed bk_section_check) to f with
 * every <table> of more than min_rows rows, not already inside <details>,
 * folded: <details class="fold"><summary>N rows: HEADER CELLS</summary>
 * TABLE</details>, the summary line the table's header cells (their text,
 * as escaped as the section has it), cut after whole cells at about 160
 * characters. Everything else is copied byte for byte. Returns the number
 * of tables folded. */
int bk_page_fold(FILE *f, const char *text, size_t len, int min_rows);

/* The link from the folder of the page at page_path to the folder dir,
 * relative ("./search/vf2d/", "../x/"), ending in '/': both resolved with
 * realpath (the page's folder must exist; the page need not). It always
 * starts with "./" or "../", so a folder named "javascript:x" is a path, not
 * a URL scheme, in an href. Returns 0, or
 * -1 with err "PATH: cannot be resolved: REASON". */
int bk_page_rel_dir(const char *page_path, const char *dir, char *out, size_t outlen, char *err, size_t errlen);

#endif
