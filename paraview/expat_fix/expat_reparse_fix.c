/* Preloaded into ParaView (LD_PRELOAD): turns expat's reparse deferral off in every parser VTK
 * creates.
 *
 * Debian 12's expat (2.5.0-1+deb12u1 and later) carries the fix for CVE-2023-52425, which defers
 * reparsing of large tokens. VTK 9.2, inside Debian's ParaView 5.11, reads XML with raw appended
 * binary data by stopping the parser at the data; with deferral the parser has read past it and
 * fails ("not well-formed (invalid token)"). ParaView moves unstructured data between MPI ranks
 * in that form (vtkDIYUtilities), so without this every redistribution for ordered compositing
 * loses the data sent between ranks. VTK 9.3 turns the deferral off itself; this does the same
 * from outside. Expat without XML_SetReparseDeferralEnabled is left as it is.
 *
 * Only XML_ParserCreate is wrapped: it is the one constructor VTK's vtkXMLParser calls. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stddef.h>

typedef struct XML_ParserStruct* XML_Parser;
typedef unsigned char XML_Bool;
typedef XML_Parser (*create_fn)(const char* encoding);
typedef XML_Bool (*set_deferral_fn)(XML_Parser parser, XML_Bool enabled);

XML_Parser XML_ParserCreate(const char* encoding) {
    static create_fn create = NULL;
    static set_deferral_fn set_deferral = NULL;
    if (!create) {
        create = (create_fn)dlsym(RTLD_NEXT, "XML_ParserCreate");
        set_deferral = (set_deferral_fn)dlsym(RTLD_NEXT, "XML_SetReparseDeferralEnabled");
    }
    XML_Parser parser = create ? create(encoding) : NULL;
    if (parser && set_deferral) set_deferral(parser, 0);
    return parser;
}
