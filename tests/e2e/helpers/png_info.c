/* Decode a PNG with libpng, every row, and print what the e2e scripts check:
 *   png_info FILE   ->  "size WxH" then one "KEY=TEXT" line per text chunk
 * (tEXt or iTXt, in file order). Exit 1 with a message if it does not
 * decode. */
#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>

static int dump(FILE *fp, const char *path)
{
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    png_bytep row = NULL;
    if (!png || !info) {
        fprintf(stderr, "png_info: %s: out of memory\n", path);
        return 1;
    }
    if (setjmp(png_jmpbuf(png))) {
        fprintf(stderr, "png_info: %s: does not decode\n", path);
        png_destroy_read_struct(&png, &info, NULL);
        free(row);
        return 1;
    }
    png_init_io(png, fp);
    png_read_info(png, info);
    png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
    row = malloc(png_get_rowbytes(png, info));
    if (!row)
        png_error(png, "out of memory");
    for (png_uint_32 y = 0; y < h; y++)
        png_read_row(png, row, NULL);
    png_read_end(png, info);
    printf("size %lux%lu\n", (unsigned long)w, (unsigned long)h);
    png_textp texts;
    int n = 0;
    png_get_text(png, info, &texts, &n);
    for (int i = 0; i < n; i++)
        printf("%s=%s\n", texts[i].key, texts[i].text);
    free(row);
    png_destroy_read_struct(&png, &info, NULL);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: png_info FILE.png\n");
        return 2;
    }
    FILE *fp = fopen(argv[1], "rb");
    if (!fp) {
        perror(argv[1]);
        return 1;
    }
    int rc = dump(fp, argv[1]);
    fclose(fp);
    return rc;
}
