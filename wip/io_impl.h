/* ------------------------------------------------------------------------------------- */
/* io                                                                                    */
/* ------------------------------------------------------------------------------------- */

/* The readers work on the whole input in memory. They go over it twice: a first pass checks
   the structure and counts vertices and triangles against the bytes that are really there,
   then the mesh is allocated once at its final size and a second pass fills it. Nothing is
   allocated per line or per number, and nothing is sized by a count that a header claims. */

#if defined(__GNUC__) || defined(__clang__)
#define CLOTH__PRINTF_LIKE(f, a) __attribute__((format(printf, f, a)))
#else
#define CLOTH__PRINTF_LIKE(f, a)
#endif

/* The input of a reader and where its errors go. */
typedef struct cloth__io {
    const unsigned char *begin;
    const unsigned char *end;
    cloth_io_error *error;     /* never NULL inside the readers */
    cloth_allocator allocator; /* resolved: never the NULL allocator */
} cloth__io;

/* Character classes of the text readers: 1 white space inside a line (space, \t, \r, \v,
   \f), 2 the line break \n, 4 the comment sign #. */
#define CLOTH__CHAR_BLANK 1
#define CLOTH__CHAR_BREAK 2
#define CLOTH__CHAR_COMMENT 4
static const unsigned char cloth__char_class[256] = {
    0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 2, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    1, 0, 0, 4, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0
};

/* White space inside a line; white space including the line break; the end of a word in a
   line (white space, line break or #). */
static int cloth__is_blank(int c) { return cloth__char_class[c & 255] & CLOTH__CHAR_BLANK; }
static int cloth__is_space(int c) { return cloth__char_class[c & 255] & (CLOTH__CHAR_BLANK | CLOTH__CHAR_BREAK); }
static int cloth__ends_word(int c)
{
    return cloth__char_class[c & 255] & (CLOTH__CHAR_BLANK | CLOTH__CHAR_BREAK | CLOTH__CHAR_COMMENT);
}
static int cloth__is_digit(int c) { return (unsigned)(c - '0') < 10u; }
static int cloth__ascii_lower(int c) { return c >= 'A' && c <= 'Z' ? c + ('a' - 'A') : c; }

static const unsigned char *cloth__skip_blank(const unsigned char *p, const unsigned char *end)
{
    while (p < end && cloth__is_blank(*p)) ++p;
    return p;
}

static const unsigned char *cloth__skip_space(const unsigned char *p, const unsigned char *end)
{
    while (p < end && cloth__is_space(*p)) ++p;
    return p;
}

/* The end of the line that contains p: its '\n', or end. */
static const unsigned char *cloth__line_end(const unsigned char *p, const unsigned char *end)
{
    const unsigned char *nl = p < end ? (const unsigned char *)memchr(p, '\n', (size_t)(end - p)) : NULL;
    return nl ? nl : end;
}

/* The end of the white-space delimited token that starts at p. */
static const unsigned char *cloth__token_end(const unsigned char *p, const unsigned char *end)
{
    while (p < end && !cloth__is_space(*p)) ++p;
    return p;
}

/* Whether the token [p, e) is `word`, ignoring ASCII case. */
static int cloth__token_is(const unsigned char *p, const unsigned char *e, const char *word)
{
    size_t n = strlen(word), i;
    if ((size_t)(e - p) != n) return 0;
    for (i = 0; i < n; ++i)
        if (cloth__ascii_lower(p[i]) != cloth__ascii_lower((unsigned char)word[i])) return 0;
    return 1;
}

/* Whether [p, end) starts with `word`, ignoring ASCII case. */
static int cloth__starts_with(const unsigned char *p, const unsigned char *end, const char *word)
{
    size_t n = strlen(word);
    return (size_t)(end - p) >= n && cloth__token_is(p, p + n, word);
}

/* The length of a token to quote in a message: at most 24 bytes, never past a line break. */
static int cloth__quote_length(const unsigned char *p, const unsigned char *end)
{
    int n = 0;
    while (p + n < end && n < 24 && !cloth__is_space(p[n]) && p[n] != 0) ++n;
    return n;
}

/* The 1-based line of the byte at `at`. Only called when reporting an error. */
static int64_t cloth__line_of(const cloth__io *io, const unsigned char *at)
{
    int64_t line = 1;
    const unsigned char *p = io->begin;
    while (p < at) {
        const unsigned char *nl = (const unsigned char *)memchr(p, '\n', (size_t)(at - p));
        if (!nl) break;
        ++line;
        p = nl + 1;
    }
    return line;
}

/* Record why reading failed and return `result`. `at` is the place of the problem (NULL when
   it has none); `text` says whether it lies in text, where a line number means something. */
CLOTH__PRINTF_LIKE(5, 6)
static cloth_result cloth__io_fail(const cloth__io *io, cloth_result result, const unsigned char *at, int text,
                                   const char *format, ...)
{
    cloth_io_error *e = io->error;
    va_list args;
    if (at) {
        if (at > io->end) at = io->end;
        e->byte_offset = (int64_t)(at - io->begin);
        e->line = text ? cloth__line_of(io, at) : 0;
    } else {
        e->byte_offset = 0;
        e->line = 0;
    }
    va_start(args, format);
    vsnprintf(e->message, sizeof e->message, format, args);
    va_end(args);
    return result;
}

/* ---- numbers -------------------------------------------------------------------------- */

/* Decimal to double, correctly rounded, without the C library (strtod depends on the locale
   and is slow). Three paths, fastest first:
     1. the mantissa has at most 15-16 digits (< 2^53) and |exponent| <= 22: one exact
        multiplication or division of two exact doubles (Clinger);
     2. up to 19 digits and |exponent| <= 64: the Eisel-Lemire algorithm, a 64 x 128-bit
        multiplication by a truncated power of ten that proves its own rounding or gives up;
     3. anything else, or when 2. gives up: exact big-integer arithmetic (slow, rare). */

static const double cloth__exact_pow10[23] = {
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11,
    1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22
};

/* 10^q for q in [CLOTH__POW10_MIN, CLOTH__POW10_MAX] as a 128-bit mantissa (high word, low
   word) normalised so that the top bit is set, truncated (rounded down). Generated with exact
   integer arithmetic: floor(10^q * 2^(127 - floor(log2(10^q)))). */
#define CLOTH__POW10_MIN (-64)
#define CLOTH__POW10_MAX 64
static const uint64_t cloth__pow10_128[CLOTH__POW10_MAX - CLOTH__POW10_MIN + 1][2] = {
    { 0xA87FEA27A539E9A5ULL, 0x3F2398D747B36224ULL }, { 0xD29FE4B18E88640EULL, 0x8EEC7F0D19A03AADULL },
    { 0x83A3EEEEF9153E89ULL, 0x1953CF68300424ACULL }, { 0xA48CEAAAB75A8E2BULL, 0x5FA8C3423C052DD7ULL },
    { 0xCDB02555653131B6ULL, 0x3792F412CB06794DULL }, { 0x808E17555F3EBF11ULL, 0xE2BBD88BBEE40BD0ULL },
    { 0xA0B19D2AB70E6ED6ULL, 0x5B6ACEAEAE9D0EC4ULL }, { 0xC8DE047564D20A8BULL, 0xF245825A5A445275ULL },
    { 0xFB158592BE068D2EULL, 0xEED6E2F0F0D56712ULL }, { 0x9CED737BB6C4183DULL, 0x55464DD69685606BULL },
    { 0xC428D05AA4751E4CULL, 0xAA97E14C3C26B886ULL }, { 0xF53304714D9265DFULL, 0xD53DD99F4B3066A8ULL },
    { 0x993FE2C6D07B7FABULL, 0xE546A8038EFE4029ULL }, { 0xBF8FDB78849A5F96ULL, 0xDE98520472BDD033ULL },
    { 0xEF73D256A5C0F77CULL, 0x963E66858F6D4440ULL }, { 0x95A8637627989AADULL, 0xDDE7001379A44AA8ULL },
    { 0xBB127C53B17EC159ULL, 0x5560C018580D5D52ULL }, { 0xE9D71B689DDE71AFULL, 0xAAB8F01E6E10B4A6ULL },
    { 0x9226712162AB070DULL, 0xCAB3961304CA70E8ULL }, { 0xB6B00D69BB55C8D1ULL, 0x3D607B97C5FD0D22ULL },
    { 0xE45C10C42A2B3B05ULL, 0x8CB89A7DB77C506AULL }, { 0x8EB98A7A9A5B04E3ULL, 0x77F3608E92ADB242ULL },
    { 0xB267ED1940F1C61CULL, 0x55F038B237591ED3ULL }, { 0xDF01E85F912E37A3ULL, 0x6B6C46DEC52F6688ULL },
    { 0x8B61313BBABCE2C6ULL, 0x2323AC4B3B3DA015ULL }, { 0xAE397D8AA96C1B77ULL, 0xABEC975E0A0D081AULL },
    { 0xD9C7DCED53C72255ULL, 0x96E7BD358C904A21ULL }, { 0x881CEA14545C7575ULL, 0x7E50D64177DA2E54ULL },
    { 0xAA242499697392D2ULL, 0xDDE50BD1D5D0B9E9ULL }, { 0xD4AD2DBFC3D07787ULL, 0x955E4EC64B44E864ULL },
    { 0x84EC3C97DA624AB4ULL, 0xBD5AF13BEF0B113EULL }, { 0xA6274BBDD0FADD61ULL, 0xECB1AD8AEACDD58EULL },
    { 0xCFB11EAD453994BAULL, 0x67DE18EDA5814AF2ULL }, { 0x81CEB32C4B43FCF4ULL, 0x80EACF948770CED7ULL },
    { 0xA2425FF75E14FC31ULL, 0xA1258379A94D028DULL }, { 0xCAD2F7F5359A3B3EULL, 0x096EE45813A04330ULL },
    { 0xFD87B5F28300CA0DULL, 0x8BCA9D6E188853FCULL }, { 0x9E74D1B791E07E48ULL, 0x775EA264CF55347DULL },
    { 0xC612062576589DDAULL, 0x95364AFE032A819DULL }, { 0xF79687AED3EEC551ULL, 0x3A83DDBD83F52204ULL },
    { 0x9ABE14CD44753B52ULL, 0xC4926A9672793542ULL }, { 0xC16D9A0095928A27ULL, 0x75B7053C0F178293ULL },
    { 0xF1C90080BAF72CB1ULL, 0x5324C68B12DD6338ULL }, { 0x971DA05074DA7BEEULL, 0xD3F6FC16EBCA5E03ULL },
    { 0xBCE5086492111AEAULL, 0x88F4BB1CA6BCF584ULL }, { 0xEC1E4A7DB69561A5ULL, 0x2B31E9E3D06C32E5ULL },
    { 0x9392EE8E921D5D07ULL, 0x3AFF322E62439FCFULL }, { 0xB877AA3236A4B449ULL, 0x09BEFEB9FAD487C2ULL },
    { 0xE69594BEC44DE15BULL, 0x4C2EBE687989A9B3ULL }, { 0x901D7CF73AB0ACD9ULL, 0x0F9D37014BF60A10ULL },
    { 0xB424DC35095CD80FULL, 0x538484C19EF38C94ULL }, { 0xE12E13424BB40E13ULL, 0x2865A5F206B06FB9ULL },
    { 0x8CBCCC096F5088CBULL, 0xF93F87B7442E45D3ULL }, { 0xAFEBFF0BCB24AAFEULL, 0xF78F69A51539D748ULL },
    { 0xDBE6FECEBDEDD5BEULL, 0xB573440E5A884D1BULL }, { 0x89705F4136B4A597ULL, 0x31680A88F8953030ULL },
    { 0xABCC77118461CEFCULL, 0xFDC20D2B36BA7C3DULL }, { 0xD6BF94D5E57A42BCULL, 0x3D32907604691B4CULL },
    { 0x8637BD05AF6C69B5ULL, 0xA63F9A49C2C1B10FULL }, { 0xA7C5AC471B478423ULL, 0x0FCF80DC33721D53ULL },
    { 0xD1B71758E219652BULL, 0xD3C36113404EA4A8ULL }, { 0x83126E978D4FDF3BULL, 0x645A1CAC083126E9ULL },
    { 0xA3D70A3D70A3D70AULL, 0x3D70A3D70A3D70A3ULL }, { 0xCCCCCCCCCCCCCCCCULL, 0xCCCCCCCCCCCCCCCCULL },
    { 0x8000000000000000ULL, 0x0000000000000000ULL }, { 0xA000000000000000ULL, 0x0000000000000000ULL },
    { 0xC800000000000000ULL, 0x0000000000000000ULL }, { 0xFA00000000000000ULL, 0x0000000000000000ULL },
    { 0x9C40000000000000ULL, 0x0000000000000000ULL }, { 0xC350000000000000ULL, 0x0000000000000000ULL },
    { 0xF424000000000000ULL, 0x0000000000000000ULL }, { 0x9896800000000000ULL, 0x0000000000000000ULL },
    { 0xBEBC200000000000ULL, 0x0000000000000000ULL }, { 0xEE6B280000000000ULL, 0x0000000000000000ULL },
    { 0x9502F90000000000ULL, 0x0000000000000000ULL }, { 0xBA43B74000000000ULL, 0x0000000000000000ULL },
    { 0xE8D4A51000000000ULL, 0x0000000000000000ULL }, { 0x9184E72A00000000ULL, 0x0000000000000000ULL },
    { 0xB5E620F480000000ULL, 0x0000000000000000ULL }, { 0xE35FA931A0000000ULL, 0x0000000000000000ULL },
    { 0x8E1BC9BF04000000ULL, 0x0000000000000000ULL }, { 0xB1A2BC2EC5000000ULL, 0x0000000000000000ULL },
    { 0xDE0B6B3A76400000ULL, 0x0000000000000000ULL }, { 0x8AC7230489E80000ULL, 0x0000000000000000ULL },
    { 0xAD78EBC5AC620000ULL, 0x0000000000000000ULL }, { 0xD8D726B7177A8000ULL, 0x0000000000000000ULL },
    { 0x878678326EAC9000ULL, 0x0000000000000000ULL }, { 0xA968163F0A57B400ULL, 0x0000000000000000ULL },
    { 0xD3C21BCECCEDA100ULL, 0x0000000000000000ULL }, { 0x84595161401484A0ULL, 0x0000000000000000ULL },
    { 0xA56FA5B99019A5C8ULL, 0x0000000000000000ULL }, { 0xCECB8F27F4200F3AULL, 0x0000000000000000ULL },
    { 0x813F3978F8940984ULL, 0x4000000000000000ULL }, { 0xA18F07D736B90BE5ULL, 0x5000000000000000ULL },
    { 0xC9F2C9CD04674EDEULL, 0xA400000000000000ULL }, { 0xFC6F7C4045812296ULL, 0x4D00000000000000ULL },
    { 0x9DC5ADA82B70B59DULL, 0xF020000000000000ULL }, { 0xC5371912364CE305ULL, 0x6C28000000000000ULL },
    { 0xF684DF56C3E01BC6ULL, 0xC732000000000000ULL }, { 0x9A130B963A6C115CULL, 0x3C7F400000000000ULL },
    { 0xC097CE7BC90715B3ULL, 0x4B9F100000000000ULL }, { 0xF0BDC21ABB48DB20ULL, 0x1E86D40000000000ULL },
    { 0x96769950B50D88F4ULL, 0x1314448000000000ULL }, { 0xBC143FA4E250EB31ULL, 0x17D955A000000000ULL },
    { 0xEB194F8E1AE525FDULL, 0x5DCFAB0800000000ULL }, { 0x92EFD1B8D0CF37BEULL, 0x5AA1CAE500000000ULL },
    { 0xB7ABC627050305ADULL, 0xF14A3D9E40000000ULL }, { 0xE596B7B0C643C719ULL, 0x6D9CCD05D0000000ULL },
    { 0x8F7E32CE7BEA5C6FULL, 0xE4820023A2000000ULL }, { 0xB35DBF821AE4F38BULL, 0xDDA2802C8A800000ULL },
    { 0xE0352F62A19E306EULL, 0xD50B2037AD200000ULL }, { 0x8C213D9DA502DE45ULL, 0x4526F422CC340000ULL },
    { 0xAF298D050E4395D6ULL, 0x9670B12B7F410000ULL }, { 0xDAF3F04651D47B4CULL, 0x3C0CDD765F114000ULL },
    { 0x88D8762BF324CD0FULL, 0xA5880A69FB6AC800ULL }, { 0xAB0E93B6EFEE0053ULL, 0x8EEA0D047A457A00ULL },
    { 0xD5D238A4ABE98068ULL, 0x72A4904598D6D880ULL }, { 0x85A36366EB71F041ULL, 0x47A6DA2B7F864750ULL },
    { 0xA70C3C40A64E6C51ULL, 0x999090B65F67D924ULL }, { 0xD0CF4B50CFE20765ULL, 0xFFF4B4E3F741CF6DULL },
    { 0x82818F1281ED449FULL, 0xBFF8F10E7A8921A4ULL }, { 0xA321F2D7226895C7ULL, 0xAFF72D52192B6A0DULL },
    { 0xCBEA6F8CEB02BB39ULL, 0x9BF4F8A69F764490ULL }, { 0xFEE50B7025C36A08ULL, 0x02F236D04753D5B4ULL },
    { 0x9F4F2726179A2245ULL, 0x01D762422C946590ULL }, { 0xC722F0EF9D80AAD6ULL, 0x424D3AD2B7B97EF5ULL },
    { 0xF8EBAD2B84E0D58BULL, 0xD2E0898765A7DEB2ULL }, { 0x9B934C3B330C8577ULL, 0x63CC55F49F88EB2FULL },
    { 0xC2781F49FFCFA6D5ULL, 0x3CBF6B71C76B25FBULL },
};

static int cloth__clz64(uint64_t x) /* x != 0 */
{
#if defined(__GNUC__) || defined(__clang__)
    return __builtin_clzll((unsigned long long)x);
#else
    int n = 0;
    while (!(x & 0x8000000000000000ULL)) { x <<= 1; ++n; }
    return n;
#endif
}

/* The full 128-bit product of two 64-bit numbers (one instruction where the compiler has a
   128-bit type, four 32-bit products elsewhere). */
#if defined(__SIZEOF_INT128__) && (defined(__GNUC__) || defined(__clang__))
__extension__ typedef unsigned __int128 cloth__uint128;
static void cloth__mul_64x64(uint64_t a, uint64_t b, uint64_t *hi, uint64_t *lo)
{
    cloth__uint128 p = (cloth__uint128)a * b;
    *hi = (uint64_t)(p >> 64);
    *lo = (uint64_t)p;
}
#else
static void cloth__mul_64x64(uint64_t a, uint64_t b, uint64_t *hi, uint64_t *lo)
{
    uint64_t a0 = a & 0xFFFFFFFFu, a1 = a >> 32, b0 = b & 0xFFFFFFFFu, b1 = b >> 32;
    uint64_t p00 = a0 * b0, p01 = a0 * b1, p10 = a1 * b0, p11 = a1 * b1;
    uint64_t mid = (p00 >> 32) + (p01 & 0xFFFFFFFFu) + (p10 & 0xFFFFFFFFu);
    *lo = (mid << 32) | (p00 & 0xFFFFFFFFu);
    *hi = p11 + (p01 >> 32) + (p10 >> 32) + (mid >> 32);
}
#endif

/* floor(q * log2(10)) for |q| < 1000, as 217706 / 2^16 approximates log2(10). */
static int cloth__floor_log2_pow10(int q)
{
    long v = 217706L * q;
    return v >= 0 ? (int)(v >> 16) : -(int)((-v + 65535) >> 16);
}

/* Eisel-Lemire: w * 10^q for 0 < w < 2^64 into *out, or 0 when it cannot decide (the exponent
   is outside the table, the result is subnormal or infinite, or too close to a halfway point). */
static int cloth__eisel_lemire(uint64_t w, int q, int negative, double *out)
{
    const uint64_t *t;
    uint64_t hi, lo, mantissa, bits;
    int shift, msb;
    long e2;
    if (q < CLOTH__POW10_MIN || q > CLOTH__POW10_MAX || w == 0) return 0;
    t = cloth__pow10_128[q - CLOTH__POW10_MIN];
    shift = cloth__clz64(w);
    w <<= shift;
    e2 = (long)cloth__floor_log2_pow10(q) + 64 + 1023 - shift;
    cloth__mul_64x64(w, t[0], &hi, &lo);
    if ((hi & 0x1FF) == 0x1FF && lo + w < w) {
        /* The truncation of the table may matter: bring in its low word. */
        uint64_t yhi, ylo, mhi = hi, mlo;
        cloth__mul_64x64(w, t[1], &yhi, &ylo);
        mlo = lo + yhi;
        if (mlo < lo) ++mhi;
        if ((mhi & 0x1FF) == 0x1FF && mlo + 1 == 0 && ylo + w < w) return 0;
        hi = mhi;
        lo = mlo;
    }
    msb = (int)(hi >> 63);
    mantissa = hi >> (msb + 9);
    e2 -= 1 ^ msb;
    if (lo == 0 && (hi & 0x1FF) == 0 && (mantissa & 3) == 1) return 0; /* maybe exactly halfway */
    mantissa += mantissa & 1;
    mantissa >>= 1;
    if (mantissa >> 53) {
        mantissa >>= 1;
        ++e2;
    }
    if (e2 <= 0 || e2 >= 0x7FF) return 0;
    bits = ((uint64_t)e2 << 52) | (mantissa & 0xFFFFFFFFFFFFFULL);
    if (negative) bits |= 0x8000000000000000ULL;
    memcpy(out, &bits, sizeof bits);
    return 1;
}

/* Unsigned big integers for the exact path: little-endian 32-bit limbs. 132 limbs hold the
   largest intermediate (800 significant digits scaled by up to 2^1126 or 10^1124). */
#define CLOTH__BIG_LIMBS 132
#define CLOTH__SLOW_DIGITS 800
typedef struct cloth__big {
    int n;
    uint32_t d[CLOTH__BIG_LIMBS];
} cloth__big;

static void cloth__big_trim(cloth__big *b)
{
    while (b->n > 0 && b->d[b->n - 1] == 0) --b->n;
}

static void cloth__big_mul_add(cloth__big *b, uint32_t m, uint32_t a)
{
    uint64_t carry = a;
    int i;
    for (i = 0; i < b->n; ++i) {
        uint64_t t = (uint64_t)b->d[i] * m + carry;
        b->d[i] = (uint32_t)t;
        carry = t >> 32;
    }
    if (carry && b->n < CLOTH__BIG_LIMBS) b->d[b->n++] = (uint32_t)carry;
}

static void cloth__big_mul_pow10(cloth__big *b, long e)
{
    static const uint32_t small[9] = { 1, 10, 100, 1000, 10000, 100000, 1000000, 10000000, 100000000 };
    for (; e >= 9; e -= 9) cloth__big_mul_add(b, 1000000000u, 0);
    if (e > 0) cloth__big_mul_add(b, small[e], 0);
}

static void cloth__big_shl(cloth__big *b, long bits)
{
    int words = (int)(bits / 32), s = (int)(bits % 32), i, n = b->n;
    if (n == 0 || bits <= 0) return;
    if (n + words + 1 > CLOTH__BIG_LIMBS) words = CLOTH__BIG_LIMBS - n - 1; /* unreachable by the bounds above */
    if (s) {
        b->d[n + words] = b->d[n - 1] >> (32 - s);
        for (i = n - 1; i > 0; --i) b->d[i + words] = (b->d[i] << s) | (b->d[i - 1] >> (32 - s));
        b->d[words] = b->d[0] << s;
        b->n = n + words + 1;
    } else {
        for (i = n - 1; i >= 0; --i) b->d[i + words] = b->d[i];
        b->n = n + words;
    }
    for (i = 0; i < words; ++i) b->d[i] = 0;
    cloth__big_trim(b);
}

static void cloth__big_shr1(cloth__big *b)
{
    int i;
    for (i = 0; i < b->n; ++i) b->d[i] = (b->d[i] >> 1) | (i + 1 < b->n ? b->d[i + 1] << 31 : 0);
    cloth__big_trim(b);
}

static int cloth__big_cmp(const cloth__big *a, const cloth__big *b)
{
    int i;
    if (a->n != b->n) return a->n < b->n ? -1 : 1;
    for (i = a->n - 1; i >= 0; --i)
        if (a->d[i] != b->d[i]) return a->d[i] < b->d[i] ? -1 : 1;
    return 0;
}

static void cloth__big_sub(cloth__big *a, const cloth__big *b) /* a -= b, with a >= b */
{
    int64_t borrow = 0;
    int i;
    for (i = 0; i < a->n; ++i) {
        int64_t t = (int64_t)a->d[i] - (i < b->n ? (int64_t)b->d[i] : 0) - borrow;
        borrow = t < 0;
        a->d[i] = (uint32_t)(t + (borrow ? ((int64_t)1 << 32) : 0));
    }
    cloth__big_trim(a);
}

static long cloth__big_bitlen(const cloth__big *b)
{
    uint32_t top;
    long n;
    if (b->n == 0) return 0;
    top = b->d[b->n - 1];
    n = 32L * (b->n - 1);
    while (top) { ++n; top >>= 1; }
    return n;
}

/* The exact path: the number in [p, end) (already known to be well formed) as the nearest
   double, ties to even. value = D * 10^e10 with D the first 800 significant digits; a nonzero
   digit beyond them only breaks an exact tie (800 digits are more than the 768 that can
   separate two doubles). The result is q * 2^k with q = round(D * 10^e10 / 2^k). */
static double cloth__decimal_exact(const unsigned char *p, const unsigned char *end)
{
    cloth__big a, b, t;
    int negative = 0, digits = 0, sticky = 0, chunk_len = 0;
    long e10 = 0, position, d, e2, k, i;
    uint32_t chunk = 0;
    uint64_t q = 0;
    double value;
    a.n = 0;
    if (p < end && (*p == '+' || *p == '-')) negative = *p++ == '-';
    for (; p < end && cloth__is_digit(*p); ++p) {
        int c = *p - '0';
        if (digits == 0 && c == 0) continue;
        if (digits < CLOTH__SLOW_DIGITS) {
            chunk = chunk * 10 + (uint32_t)c;
            if (++chunk_len == 9) { cloth__big_mul_add(&a, 1000000000u, chunk); chunk = 0; chunk_len = 0; }
            ++digits;
        } else {
            ++e10;
            sticky |= c != 0;
        }
    }
    if (p < end && *p == '.') {
        for (++p; p < end && cloth__is_digit(*p); ++p) {
            int c = *p - '0';
            if (digits == 0 && c == 0) { --e10; continue; }
            if (digits < CLOTH__SLOW_DIGITS) {
                chunk = chunk * 10 + (uint32_t)c;
                if (++chunk_len == 9) { cloth__big_mul_add(&a, 1000000000u, chunk); chunk = 0; chunk_len = 0; }
                ++digits;
                --e10;
            } else {
                sticky |= c != 0;
            }
        }
    }
    if (chunk_len) {
        uint32_t scale = 1;
        for (i = 0; i < chunk_len; ++i) scale *= 10;
        cloth__big_mul_add(&a, scale, chunk);
    }
    if (p < end && (*p == 'e' || *p == 'E')) {
        int eneg = 0;
        long ev = 0;
        ++p;
        if (p < end && (*p == '+' || *p == '-')) eneg = *p++ == '-';
        for (; p < end && cloth__is_digit(*p); ++p)
            if (ev < 100000000L) ev = ev * 10 + (*p - '0');
        e10 += eneg ? -ev : ev;
    }
    if (digits == 0) return negative ? -0.0 : 0.0;
    position = digits + e10; /* 10^(position-1) <= value < 10^position */
    if (position > 310) return negative ? -HUGE_VAL : HUGE_VAL;
    if (position < -324) return negative ? -0.0 : 0.0;
    b.n = 1;
    b.d[0] = 1;
    if (e10 >= 0) cloth__big_mul_pow10(&a, e10);
    else cloth__big_mul_pow10(&b, -e10);
    /* e2 = floor(log2(a / b)) */
    d = cloth__big_bitlen(&a) - cloth__big_bitlen(&b);
    if (d >= 0) {
        t = b;
        cloth__big_shl(&t, d);
        e2 = cloth__big_cmp(&a, &t) >= 0 ? d : d - 1;
    } else {
        t = a;
        cloth__big_shl(&t, -d);
        e2 = cloth__big_cmp(&t, &b) >= 0 ? d : d - 1;
    }
    if (e2 > 1023) return negative ? -HUGE_VAL : HUGE_VAL;
    k = e2 - 52;
    if (k < -1074) k = -1074;
    if (k < 0) cloth__big_shl(&a, -k);
    else cloth__big_shl(&b, k);
    /* q = floor(a / b) < 2^53 by the choice of k, by shift and subtract; a keeps the rest. */
    t = b;
    cloth__big_shl(&t, 53);
    for (i = 53; i >= 0; --i) {
        if (cloth__big_cmp(&a, &t) >= 0) {
            cloth__big_sub(&a, &t);
            q |= (uint64_t)1 << i;
        }
        cloth__big_shr1(&t);
    }
    cloth__big_shl(&a, 1);
    {
        int c = cloth__big_cmp(&a, &b); /* twice the remainder against the divisor */
        if (c > 0 || (c == 0 && (sticky || (q & 1)))) ++q;
    }
    value = ldexp((double)q, (int)k);
    return negative ? -value : value;
}

/* Eight ASCII bytes at p as a little-endian word: one load on little-endian machines. */
static uint64_t cloth__load_8_bytes(const unsigned char *p)
{
#if defined(__BYTE_ORDER__) && defined(__ORDER_LITTLE_ENDIAN__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    uint64_t v;
    memcpy(&v, p, sizeof v);
    return v;
#else
    return (uint64_t)p[0] | ((uint64_t)p[1] << 8) | ((uint64_t)p[2] << 16) | ((uint64_t)p[3] << 24) | ((uint64_t)p[4] << 32) |
           ((uint64_t)p[5] << 40) | ((uint64_t)p[6] << 48) | ((uint64_t)p[7] << 56);
#endif
}

/* Whether all eight bytes of v are decimal digits: each byte's high nibble is 3, and stays 3
   after adding 6 (a carry out of a byte only happens from a byte that already fails). */
static int cloth__eight_digits(uint64_t v)
{
    return ((v & 0xF0F0F0F0F0F0F0F0ULL) | (((v + 0x0606060606060606ULL) & 0xF0F0F0F0F0F0F0F0ULL) >> 4)) == 0x3333333333333333ULL;
}

/* The value of eight decimal digits (first digit in the low byte), combining pairs, then
   pairs of pairs, then the two halves with multiplications (SWAR). */
static uint32_t cloth__eight_digits_value(uint64_t v)
{
    v -= 0x3030303030303030ULL;
    v = v * 10 + (v >> 8);
    v = ((v & 0x000000FF000000FFULL) * (100 + (1000000ULL << 32)) +
         ((v >> 16) & 0x000000FF000000FFULL) * (1 + (10000ULL << 32))) >> 32;
    return (uint32_t)v;
}

/* Scan a decimal number at p: an optional sign, digits with an optional point, an optional
   exponent; also "nan", "inf" and "infinity" in any case (so that the caller can report
   CLOTH_ERROR_NOT_FINITE rather than a parse error). Returns the end of the number and the
   correctly rounded double in *out, or NULL when no number starts at p. The caller checks
   what follows. The first 19 significant digits are gathered in w (eight at a time where
   they allow), the value being w * 10^q. */
static const unsigned char *cloth__scan_double(const unsigned char *p, const unsigned char *end, double *out)
{
    const unsigned char *start = p;
    uint64_t w = 0;
    int negative = 0, digits = 0, truncated = 0, any = 0;
    long q = 0;
    if (p < end && (*p == '+' || *p == '-')) negative = *p++ == '-';
    if (p < end && (*p == 'n' || *p == 'N' || *p == 'i' || *p == 'I')) {
        if (cloth__starts_with(p, end, "nan")) {
            *out = NAN;
            return p + 3;
        }
        if (cloth__starts_with(p, end, "infinity")) {
            *out = negative ? -HUGE_VAL : HUGE_VAL;
            return p + 8;
        }
        if (cloth__starts_with(p, end, "inf")) {
            *out = negative ? -HUGE_VAL : HUGE_VAL;
            return p + 3;
        }
        return NULL;
    }
    /* integer part: leading zeros, then significant digits */
    for (; p < end && *p == '0'; ++p) any = 1;
    while (digits <= 11 && end - p >= 8) {
        uint64_t v = cloth__load_8_bytes(p);
        if (!cloth__eight_digits(v)) break;
        w = w * 100000000u + cloth__eight_digits_value(v);
        digits += 8;
        p += 8;
        any = 1;
    }
    for (; p < end && cloth__is_digit(*p); ++p) {
        any = 1;
        if (digits < 19) {
            w = w * 10 + (unsigned)(*p - '0');
            ++digits;
        } else {
            ++q;
            truncated |= *p != '0';
        }
    }
    if (p < end && *p == '.') {
        ++p;
        if (digits == 0)
            for (; p < end && *p == '0'; ++p) { /* zeros after the point that lead */
                any = 1;
                --q;
            }
        while (digits <= 11 && end - p >= 8) {
            uint64_t v = cloth__load_8_bytes(p);
            if (!cloth__eight_digits(v)) break;
            w = w * 100000000u + cloth__eight_digits_value(v);
            digits += 8;
            q -= 8;
            p += 8;
            any = 1;
        }
        for (; p < end && cloth__is_digit(*p); ++p) {
            any = 1;
            if (digits < 19) {
                w = w * 10 + (unsigned)(*p - '0');
                ++digits;
                --q;
            } else {
                truncated |= *p != '0';
            }
        }
    }
    if (!any) return NULL;
    if (p < end && (*p == 'e' || *p == 'E')) {
        const unsigned char *e = p + 1;
        int eneg = 0;
        long ev = 0;
        if (e < end && (*e == '+' || *e == '-')) eneg = *e++ == '-';
        if (e < end && cloth__is_digit(*e)) {
            for (; e < end && cloth__is_digit(*e); ++e)
                if (ev < 100000000L) ev = ev * 10 + (*e - '0');
            q += eneg ? -ev : ev;
            p = e;
        }
    }
    if (w == 0 && !truncated) {
        *out = negative ? -0.0 : 0.0;
        return p;
    }
    if (!truncated) {
#if !defined(FLT_EVAL_METHOD) || FLT_EVAL_METHOD == 0
        if (w <= ((uint64_t)1 << 53) && q >= -22 && q <= 22) {
            double v = (double)w;
            v = q >= 0 ? v * cloth__exact_pow10[q] : v / cloth__exact_pow10[-q];
            *out = negative ? -v : v;
            return p;
        }
#endif
        if (q >= CLOTH__POW10_MIN && q <= CLOTH__POW10_MAX && cloth__eisel_lemire(w, (int)q, negative, out)) return p;
    }
    *out = cloth__decimal_exact(start, p);
    return p;
}

/* Scan an optionally signed decimal integer at p; NULL when there is none. Values beyond
   +-2^62 saturate (they are out of every range anyway). */
static const unsigned char *cloth__scan_int(const unsigned char *p, const unsigned char *end, int64_t *out)
{
    const unsigned char *digits, *limit;
    int negative = 0;
    int64_t v = 0;
    if (p < end && (*p == '+' || *p == '-')) negative = *p++ == '-';
    digits = p;
    while (p < end && *p == '0') ++p;
    limit = end - p > 18 ? p + 18 : end;
    for (; p < limit && cloth__is_digit(*p); ++p) v = v * 10 + (*p - '0');
    if (p < end && cloth__is_digit(*p)) {
        v = (int64_t)1 << 62;
        while (p < end && cloth__is_digit(*p)) ++p;
    }
    if (p == digits) return NULL;
    *out = negative ? -v : v;
    return p;
}

/* ---- fields of text formats ------------------------------------------------------------ */

/* Whether p ends a number or index in a line of text: the end of the line (eol, or a line
   break before it), white space or '#'. */
static int cloth__ends_field(const unsigned char *p, const unsigned char *eol)
{
    return p >= eol || cloth__ends_word(*p);
}

/* Whether p is at the end of a line's content: eol, a line break or a comment. */
static int cloth__ends_content(const unsigned char *p, const unsigned char *eol)
{
    return p >= eol || *p == '\n' || *p == '#';
}

/* Read one real of a line at *pp (leading blanks skipped) into *out; `what` names it in
   messages. A number must be finite after rounding to cloth_real. */
static cloth_result cloth__text_real(const cloth__io *io, const unsigned char **pp, const unsigned char *eol,
                                     cloth_real *out, const char *what)
{
    const unsigned char *p = cloth__skip_blank(*pp, eol), *q;
    double d = 0;
    if (cloth__ends_content(p, eol)) return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "%s: a number is missing", what);
    q = cloth__scan_double(p, eol, &d);
    if (!q || !cloth__ends_field(q, eol))
        return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "%s: '%.*s' is not a number", what, cloth__quote_length(p, eol), p);
    *out = (cloth_real)d;
    if (!cloth__is_finite(*out))
        return cloth__io_fail(io, CLOTH_ERROR_NOT_FINITE, p, 1, "%s: %.*s is not a finite number", what,
                              cloth__quote_length(p, eol), p);
    *pp = q;
    return CLOTH_SUCCESS;
}

/* Read one integer of a line at *pp (leading blanks skipped). */
static cloth_result cloth__text_int(const cloth__io *io, const unsigned char **pp, const unsigned char *eol, int64_t *out,
                                    const char *what)
{
    const unsigned char *p = cloth__skip_blank(*pp, eol), *q;
    if (cloth__ends_content(p, eol)) return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "%s: a number is missing", what);
    q = cloth__scan_int(p, eol, out);
    if (!q || !cloth__ends_field(q, eol))
        return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "%s: '%.*s' is not an integer", what, cloth__quote_length(p, eol), p);
    *pp = q;
    return CLOTH_SUCCESS;
}

/* Allocate the output mesh once the counts are known, with `text` saying whether the input
   is text (for the place of an empty-mesh error, which is the end of the input). */
static cloth_result cloth__io_mesh_alloc(const cloth__io *io, cloth_mesh *mesh, int64_t vertex_count, int64_t triangle_count,
                                         int with_uv, int text)
{
    cloth_result r;
    if (vertex_count <= 0) return cloth__io_fail(io, CLOTH_ERROR_EMPTY_MESH, io->end, text, "the file has no vertices");
    if (triangle_count <= 0) return cloth__io_fail(io, CLOTH_ERROR_EMPTY_MESH, io->end, text, "the file has no triangles");
    if (vertex_count > INT32_MAX || triangle_count > INT32_MAX)
        return cloth__io_fail(io, CLOTH_ERROR_SIZE_OVERFLOW, io->end, text, "%lld vertices and %lld triangles exceed int32_t",
                              (long long)vertex_count, (long long)triangle_count);
    r = cloth_mesh_alloc(mesh, (int32_t)vertex_count, (int32_t)triangle_count, with_uv, &io->allocator);
    if (r != CLOTH_SUCCESS)
        return cloth__io_fail(io, r, NULL, 0, "cannot allocate a mesh of %lld vertices and %lld triangles",
                              (long long)vertex_count, (long long)triangle_count);
    return CLOTH_SUCCESS;
}

/* Skip a UTF-8 byte order mark. */
static const unsigned char *cloth__skip_bom(const unsigned char *p, const unsigned char *end)
{
    return end - p >= 3 && p[0] == 0xEF && p[1] == 0xBB && p[2] == 0xBF ? p + 3 : p;
}

/* ---- OBJ ----------------------------------------------------------------------------- */

typedef enum cloth__obj_statement {
    CLOTH__OBJ_VERTEX,
    CLOTH__OBJ_TEXCOORD,
    CLOTH__OBJ_FACE,
    CLOTH__OBJ_SKIPPED,
    CLOTH__OBJ_UNKNOWN
} cloth__obj_statement;

/* What the keyword [k, e) of a line is: every statement of the OBJ specification is known;
   v, vt and f are read and the others skipped. */
static cloth__obj_statement cloth__obj_keyword(const unsigned char *k, const unsigned char *e)
{
    static const char *const skipped[] = {
        "vn", "vp", "o", "g", "s", "l", "p", "usemtl", "mtllib", "cstype", "deg", "bmat", "step", "curv", "curv2",
        "surf", "parm", "trim", "hole", "scrv", "sp", "end", "con", "mg", "bevel", "c_interp", "d_interp", "lod",
        "shadow_obj", "trace_obj", "ctech", "stech", "maplib", "usemap"
    };
    size_t n = (size_t)(e - k), i;
    if (n == 1 && k[0] == 'v') return CLOTH__OBJ_VERTEX;
    if (n == 1 && k[0] == 'f') return CLOTH__OBJ_FACE;
    if (n == 2 && k[0] == 'v' && k[1] == 't') return CLOTH__OBJ_TEXCOORD;
    for (i = 0; i < sizeof skipped / sizeof skipped[0]; ++i)
        if (strlen(skipped[i]) == n && memcmp(skipped[i], k, n) == 0) return CLOTH__OBJ_SKIPPED;
    return CLOTH__OBJ_UNKNOWN;
}

/* The keyword of a line: from p (after leading blanks) to white space or '#'. */
static const unsigned char *cloth__obj_keyword_end(const unsigned char *p, const unsigned char *eol)
{
    while (p < eol && !cloth__ends_word(*p)) ++p;
    return p;
}

/* The start of the next line after p, from where a statement's reading stopped (usually
   its line break already). */
static const unsigned char *cloth__next_line(const unsigned char *p, const unsigned char *end)
{
    p = cloth__skip_blank(p, end);
    if (p < end && *p != '\n') p = cloth__line_end(p, end);
    return p < end ? p + 1 : end;
}

/* Resolve an OBJ index (1-based, or negative relative to the `defined` items above) against
   `total` items; -1 when out of range. */
static int64_t cloth__obj_resolve(int64_t index, int64_t defined, int64_t total)
{
    if (index > 0) return index <= total ? index - 1 : -1;
    if (index < 0) return defined + index >= 0 ? defined + index : -1;
    return -1;
}

/* Read one face corner "v", "v/vt", "v//vn" or "v/vt/vn" at *pp. *vt is -1 without a vt. */
static cloth_result cloth__obj_corner(const cloth__io *io, const unsigned char **pp, const unsigned char *eol,
                                      int64_t vertices_above, int64_t vertex_total, int64_t texcoords_above,
                                      int64_t texcoord_total, int32_t *v, int32_t *vt)
{
    const unsigned char *start = *pp, *p;
    int64_t index = 0, resolved;
    p = cloth__scan_int(start, eol, &index);
    if (!p) return cloth__io_fail(io, CLOTH_ERROR_PARSE, start, 1, "face corner '%.*s' does not start with a vertex index",
                                  cloth__quote_length(start, eol), start);
    resolved = cloth__obj_resolve(index, vertices_above, vertex_total);
    if (resolved < 0)
        return cloth__io_fail(io, CLOTH_ERROR_INDEX_OUT_OF_RANGE, start, 1,
                              "face names vertex %lld; %lld vertices are defined above it, %lld in the file", (long long)index,
                              (long long)vertices_above, (long long)vertex_total);
    *v = (int32_t)resolved;
    *vt = -1;
    if (p < eol && *p == '/') {
        ++p;
        if (!cloth__ends_field(p, eol) && *p != '/') {
            const unsigned char *t = p;
            p = cloth__scan_int(t, eol, &index);
            if (!p) return cloth__io_fail(io, CLOTH_ERROR_PARSE, t, 1, "face corner '%.*s': bad texture coordinate index",
                                          cloth__quote_length(start, eol), start);
            resolved = cloth__obj_resolve(index, texcoords_above, texcoord_total);
            if (resolved < 0)
                return cloth__io_fail(io, CLOTH_ERROR_INDEX_OUT_OF_RANGE, t, 1,
                                      "face names texture coordinate %lld; %lld are defined above it, %lld in the file",
                                      (long long)index, (long long)texcoords_above, (long long)texcoord_total);
            *vt = (int32_t)resolved;
        }
        if (p < eol && *p == '/') {
            ++p;
            if (!cloth__ends_field(p, eol)) {
                const unsigned char *n = p;
                p = cloth__scan_int(n, eol, &index);
                if (!p) return cloth__io_fail(io, CLOTH_ERROR_PARSE, n, 1, "face corner '%.*s': bad normal index",
                                              cloth__quote_length(start, eol), start);
            }
        }
    }
    if (!cloth__ends_field(p, eol))
        return cloth__io_fail(io, CLOTH_ERROR_PARSE, start, 1, "malformed face corner '%.*s'", cloth__quote_length(start, eol),
                              start);
    *pp = p;
    return CLOTH_SUCCESS;
}

static cloth_result cloth__read_obj(const cloth__io *io, cloth_mesh *mesh)
{
    const unsigned char *begin = cloth__skip_bom(io->begin, io->end), *end = io->end, *p;
    int64_t vertex_total = 0, texcoord_total = 0, triangle_total = 0, vertices = 0, texcoords = 0, triangles = 0;
    int with_uv = 0;
    cloth_real *vt = NULL;
    int32_t *pairing = NULL;
    cloth_result r = CLOTH_SUCCESS;

    /* First pass: count, check statements and the number of corners of every face. Lines are
       read up to their line break without looking for it first. */
    for (p = begin; p < end;) {
        const unsigned char *k;
        cloth__obj_statement s;
        p = cloth__skip_blank(p, end);
        if (cloth__ends_content(p, end)) {
            p = cloth__next_line(p, end);
            continue;
        }
        k = p;
        p = cloth__obj_keyword_end(p, end);
        s = cloth__obj_keyword(k, p);
        if (s == CLOTH__OBJ_VERTEX) {
            ++vertex_total;
        } else if (s == CLOTH__OBJ_TEXCOORD) {
            ++texcoord_total;
        } else if (s == CLOTH__OBJ_FACE) {
            int64_t corners = 0;
            for (;;) {
                int slash = 0;
                p = cloth__skip_blank(p, end);
                if (cloth__ends_content(p, end)) break;
                ++corners;
                for (; p < end && !cloth__ends_word(*p); ++p) {
                    if (*p == '/' && !slash) {
                        slash = 1;
                        if (p + 1 < end && p[1] != '/' && !cloth__ends_field(p + 1, end)) with_uv = 1;
                    }
                }
            }
            if (corners < 3)
                return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "a face needs at least 3 vertices, this one has %lld",
                                      (long long)corners);
            triangle_total += corners - 2;
        } else if (s == CLOTH__OBJ_UNKNOWN) {
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "unknown OBJ statement '%.*s'", (int)(p - k > 24 ? 24 : p - k), k);
        }
        p = cloth__next_line(p, end);
    }
    r = cloth__io_mesh_alloc(io, mesh, vertex_total, triangle_total, with_uv, 1);
    if (r != CLOTH_SUCCESS) return r;
    if (with_uv) {
        if (texcoord_total > INT32_MAX) {
            r = cloth__io_fail(io, CLOTH_ERROR_SIZE_OVERFLOW, NULL, 0, "%lld texture coordinates exceed int32_t",
                               (long long)texcoord_total);
            goto done;
        }
        vt = (cloth_real *)cloth__alloc_array(&io->allocator, (size_t)texcoord_total * 2, sizeof(cloth_real));
        pairing = (int32_t *)cloth__alloc_array(&io->allocator, (size_t)vertex_total, sizeof(int32_t));
        if (!vt || !pairing) {
            r = cloth__io_fail(io, CLOTH_ERROR_OUT_OF_MEMORY, NULL, 0, "cannot allocate %lld texture coordinates",
                               (long long)texcoord_total);
            goto done;
        }
        memset(pairing, 0xFF, sizeof(int32_t) * (size_t)vertex_total); /* -1: not paired yet */
    }

    /* Second pass: read. */
    for (p = begin; p < end && r == CLOTH_SUCCESS;) {
        const unsigned char *k;
        cloth__obj_statement s;
        p = cloth__skip_blank(p, end);
        if (cloth__ends_content(p, end)) {
            p = cloth__next_line(p, end);
            continue;
        }
        k = p;
        p = cloth__obj_keyword_end(p, end);
        s = cloth__obj_keyword(k, p);
        if (s == CLOTH__OBJ_VERTEX) {
            cloth_real *x = mesh->x + 3 * vertices;
            if ((r = cloth__text_real(io, &p, end, x, "vertex x")) != CLOTH_SUCCESS) break;
            if ((r = cloth__text_real(io, &p, end, x + 1, "vertex y")) != CLOTH_SUCCESS) break;
            if ((r = cloth__text_real(io, &p, end, x + 2, "vertex z")) != CLOTH_SUCCESS) break;
            ++vertices;
        } else if (s == CLOTH__OBJ_TEXCOORD) {
            cloth_real uv[2] = { 0, 0 };
            if ((r = cloth__text_real(io, &p, end, uv, "texture coordinate u")) != CLOTH_SUCCESS) break;
            p = cloth__skip_blank(p, end);
            if (!cloth__ends_content(p, end) &&
                (r = cloth__text_real(io, &p, end, uv + 1, "texture coordinate v")) != CLOTH_SUCCESS)
                break;
            if (vt) {
                vt[2 * texcoords] = uv[0];
                vt[2 * texcoords + 1] = uv[1];
            }
            ++texcoords;
        } else if (s == CLOTH__OBJ_FACE) {
            int32_t first = -1, previous = -1, v = 0, t = -1;
            int64_t corner = 0;
            for (;;) {
                p = cloth__skip_blank(p, end);
                if (cloth__ends_content(p, end)) break;
                r = cloth__obj_corner(io, &p, end, vertices, vertex_total, texcoords, texcoord_total, &v, &t);
                if (r != CLOTH_SUCCESS) break;
                if (pairing && t >= 0 && pairing[v] < 0) pairing[v] = t;
                if (corner == 0) first = v;
                if (corner >= 2 && triangles < triangle_total) {
                    int32_t *tri = mesh->tri + 3 * triangles++;
                    tri[0] = first;
                    tri[1] = previous;
                    tri[2] = v;
                }
                previous = v;
                ++corner;
            }
        }
        p = cloth__next_line(p, end);
    }
    if (r == CLOTH_SUCCESS && with_uv) {
        int64_t i;
        for (i = 0; i < vertex_total; ++i) {
            int32_t t = pairing[i];
            mesh->uv[2 * i] = t >= 0 ? vt[2 * t] : 0;
            mesh->uv[2 * i + 1] = t >= 0 ? vt[2 * t + 1] : 0;
        }
    }
done:
    cloth__free(&io->allocator, vt);
    cloth__free(&io->allocator, pairing);
    return r;
}

/* ---- binary values (PLY and VTK) ------------------------------------------------------- */

typedef enum cloth__type {
    CLOTH__TYPE_NONE = 0,
    CLOTH__TYPE_INT8,
    CLOTH__TYPE_UINT8,
    CLOTH__TYPE_INT16,
    CLOTH__TYPE_UINT16,
    CLOTH__TYPE_INT32,
    CLOTH__TYPE_UINT32,
    CLOTH__TYPE_INT64,
    CLOTH__TYPE_UINT64,
    CLOTH__TYPE_FLOAT32,
    CLOTH__TYPE_FLOAT64
} cloth__type;

static const unsigned char cloth__type_size[11] = { 0, 1, 1, 2, 2, 4, 4, 8, 8, 4, 8 };

static int cloth__type_is_integer(int type) { return type >= CLOTH__TYPE_INT8 && type <= CLOTH__TYPE_UINT64; }

static uint32_t cloth__load_u16(const unsigned char *p, int big_endian)
{
    return big_endian ? ((uint32_t)p[0] << 8) | p[1] : ((uint32_t)p[1] << 8) | p[0];
}

static uint32_t cloth__load_u32(const unsigned char *p, int big_endian)
{
    if (big_endian) return ((uint32_t)p[0] << 24) | ((uint32_t)p[1] << 16) | ((uint32_t)p[2] << 8) | p[3];
    return ((uint32_t)p[3] << 24) | ((uint32_t)p[2] << 16) | ((uint32_t)p[1] << 8) | p[0];
}

static uint64_t cloth__load_u64(const unsigned char *p, int big_endian)
{
    uint64_t a = cloth__load_u32(p, big_endian), b = cloth__load_u32(p + 4, big_endian);
    return big_endian ? (a << 32) | b : (b << 32) | a;
}

/* The value at p of an integer type, as int64_t (uint64 values above INT64_MAX saturate). */
static int64_t cloth__load_int(const unsigned char *p, int type, int big_endian)
{
    uint64_t u;
    switch (type) {
    case CLOTH__TYPE_INT8: return p[0] >= 0x80 ? (int64_t)p[0] - 0x100 : (int64_t)p[0];
    case CLOTH__TYPE_UINT8: return p[0];
    case CLOTH__TYPE_INT16: u = cloth__load_u16(p, big_endian); return u >= 0x8000 ? (int64_t)u - 0x10000 : (int64_t)u;
    case CLOTH__TYPE_UINT16: return cloth__load_u16(p, big_endian);
    case CLOTH__TYPE_INT32:
        u = cloth__load_u32(p, big_endian);
        return u >= 0x80000000u ? (int64_t)u - ((int64_t)1 << 32) : (int64_t)u;
    case CLOTH__TYPE_UINT32: return cloth__load_u32(p, big_endian);
    case CLOTH__TYPE_INT64:
        u = cloth__load_u64(p, big_endian);
        return u >> 63 ? -(int64_t)(~u) - 1 : (int64_t)u;
    case CLOTH__TYPE_UINT64:
        u = cloth__load_u64(p, big_endian);
        return u >> 63 ? INT64_MAX : (int64_t)u;
    default: return 0;
    }
}

/* The value at p of any numeric type, as a double. */
static double cloth__load_real(const unsigned char *p, int type, int big_endian)
{
    if (type == CLOTH__TYPE_FLOAT32) {
        uint32_t bits = cloth__load_u32(p, big_endian);
        float f;
        memcpy(&f, &bits, sizeof f);
        return (double)f;
    }
    if (type == CLOTH__TYPE_FLOAT64) {
        uint64_t bits = cloth__load_u64(p, big_endian);
        double d;
        memcpy(&d, &bits, sizeof d);
        return d;
    }
    if (type == CLOTH__TYPE_INT64) {
        uint64_t u = cloth__load_u64(p, big_endian);
        return u >> 63 ? -(double)(~u) - 1.0 : (double)u;
    }
    if (type == CLOTH__TYPE_UINT64) return (double)cloth__load_u64(p, big_endian);
    return (double)cloth__load_int(p, type, big_endian);
}

/* ---- PLY ----------------------------------------------------------------------------- */

typedef enum cloth__ply_role {
    CLOTH__PLY_OTHER = 0,
    CLOTH__PLY_X, CLOTH__PLY_Y, CLOTH__PLY_Z,
    CLOTH__PLY_U, CLOTH__PLY_V, CLOTH__PLY_S, CLOTH__PLY_T, CLOTH__PLY_TEXTURE_U, CLOTH__PLY_TEXTURE_V,
    CLOTH__PLY_INDICES,
    CLOTH__PLY_ROLE_COUNT
} cloth__ply_role;

typedef struct cloth__ply_property {
    unsigned char type;       /* the value type, or the item type of a list */
    unsigned char count_type; /* the count type of a list; CLOTH__TYPE_NONE for a scalar */
    unsigned char role;       /* a cloth__ply_role */
} cloth__ply_property;

typedef struct cloth__ply_element {
    const unsigned char *line; /* its "element" line, for messages */
    const unsigned char *name;
    int name_length;
    int64_t count;
    int first_property, property_count;
    size_t stride;              /* binary: bytes per item when no property is a list, else 0 */
    const unsigned char *data;  /* where its items start (found by the first pass) */
} cloth__ply_element;

typedef struct cloth__ply {
    const cloth__io *io;
    int binary, big_endian;
    cloth__ply_element *element;
    int element_count;
    cloth__ply_property *property;
    int property_count;
    const unsigned char *body;      /* the first byte after end_header's line */
    int vertex, face;               /* element indices, -1 when absent */
    int role[CLOTH__PLY_ROLE_COUNT]; /* property index for each role, -1 when absent */
    int uv_u, uv_v;                 /* the roles that give uv, 0 when none */
    int64_t triangle_count;
    int all_triangles;              /* every face is a triangle */
} cloth__ply;

static cloth__type cloth__ply_type(const unsigned char *p, const unsigned char *e)
{
    static const struct { const char *name; cloth__type type; } names[] = {
        { "char", CLOTH__TYPE_INT8 }, { "int8", CLOTH__TYPE_INT8 }, { "uchar", CLOTH__TYPE_UINT8 },
        { "uint8", CLOTH__TYPE_UINT8 }, { "short", CLOTH__TYPE_INT16 }, { "int16", CLOTH__TYPE_INT16 },
        { "ushort", CLOTH__TYPE_UINT16 }, { "uint16", CLOTH__TYPE_UINT16 }, { "int", CLOTH__TYPE_INT32 },
        { "int32", CLOTH__TYPE_INT32 }, { "uint", CLOTH__TYPE_UINT32 }, { "uint32", CLOTH__TYPE_UINT32 },
        { "int64", CLOTH__TYPE_INT64 }, { "uint64", CLOTH__TYPE_UINT64 }, { "float", CLOTH__TYPE_FLOAT32 },
        { "float32", CLOTH__TYPE_FLOAT32 }, { "double", CLOTH__TYPE_FLOAT64 }, { "float64", CLOTH__TYPE_FLOAT64 }
    };
    size_t i;
    for (i = 0; i < sizeof names / sizeof names[0]; ++i)
        if (cloth__token_is(p, e, names[i].name)) return names[i].type;
    return CLOTH__TYPE_NONE;
}

/* Split the line [p, eol) into at most `max` blank-separated words; returns their number
   (more than max when the line has more). */
static int cloth__split_line(const unsigned char *p, const unsigned char *eol, const unsigned char **word,
                             const unsigned char **word_end, int max)
{
    int n = 0;
    for (;;) {
        p = cloth__skip_blank(p, eol);
        if (p >= eol) return n;
        if (n < max) word[n] = p;
        while (p < eol && !cloth__is_blank(*p)) ++p;
        if (n < max) word_end[n] = p;
        ++n;
    }
}

static int cloth__bytes_are(const unsigned char *p, const unsigned char *e, const char *s)
{
    size_t n = strlen(s);
    return (size_t)(e - p) == n && memcmp(p, s, n) == 0;
}

static cloth_result cloth__ply_header(cloth__ply *ply)
{
    const cloth__io *io = ply->io;
    const unsigned char *end = io->end, *p = io->begin, *eol, *w[6], *we[6];
    int lines = 0, n, have_format = 0, i;
    /* "ply" alone on the first line */
    eol = cloth__line_end(p, end);
    n = cloth__split_line(p, eol, w, we, 6);
    if (n != 1 || !cloth__bytes_are(w[0], we[0], "ply"))
        return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "not a PLY file: the first line is not 'ply'");
    /* Count the header's lines to size the tables. */
    for (p = eol < end ? eol + 1 : end;; ++lines) {
        if (p >= end) return cloth__io_fail(io, CLOTH_ERROR_TRUNCATED, end, 1, "the PLY header has no end_header line");
        eol = cloth__line_end(p, end);
        n = cloth__split_line(p, eol, w, we, 6);
        if (n == 1 && cloth__bytes_are(w[0], we[0], "end_header")) break;
        p = eol < end ? eol + 1 : end;
    }
    ply->element = (cloth__ply_element *)cloth__alloc_array(&io->allocator, (size_t)lines + 1, sizeof(cloth__ply_element));
    ply->property = (cloth__ply_property *)cloth__alloc_array(&io->allocator, (size_t)lines + 1, sizeof(cloth__ply_property));
    if (!ply->element || !ply->property)
        return cloth__io_fail(io, CLOTH_ERROR_OUT_OF_MEMORY, NULL, 0, "cannot allocate the PLY header tables");
    eol = cloth__line_end(io->begin, end);
    for (p = eol + 1;; p = eol + 1) {
        eol = cloth__line_end(p, end);
        n = cloth__split_line(p, eol, w, we, 6);
        if (n == 0) continue;
        if (n == 1 && cloth__bytes_are(w[0], we[0], "end_header")) {
            ply->body = eol < end ? eol + 1 : end;
            break;
        } else if (cloth__bytes_are(w[0], we[0], "comment") || cloth__bytes_are(w[0], we[0], "obj_info")) {
            continue;
        } else if (cloth__bytes_are(w[0], we[0], "format")) {
            if (n != 3) return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "the format line needs an encoding and a version");
            if (cloth__bytes_are(w[1], we[1], "ascii")) {
                ply->binary = 0;
            } else if (cloth__bytes_are(w[1], we[1], "binary_little_endian") ||
                       cloth__bytes_are(w[1], we[1], "binary_big_endian")) {
                ply->binary = 1;
                ply->big_endian = w[1][7] == 'b';
            } else {
                return cloth__io_fail(io, CLOTH_ERROR_UNSUPPORTED, w[1], 1, "unknown PLY encoding '%.*s'",
                                       cloth__quote_length(w[1], eol), w[1]);
            }
            if (!cloth__bytes_are(w[2], we[2], "1.0") && !cloth__bytes_are(w[2], we[2], "1"))
                return cloth__io_fail(io, CLOTH_ERROR_UNSUPPORTED, w[2], 1, "PLY version '%.*s' (only 1.0 is read)",
                                      cloth__quote_length(w[2], eol), w[2]);
            have_format = 1;
        } else if (cloth__bytes_are(w[0], we[0], "element")) {
            cloth__ply_element *e = &ply->element[ply->element_count++];
            const unsigned char *q;
            if (n != 3) return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "an element line needs a name and a count");
            memset(e, 0, sizeof *e);
            e->line = p;
            e->name = w[1];
            e->name_length = (int)(we[1] - w[1] > 32 ? 32 : we[1] - w[1]);
            q = cloth__scan_int(w[2], we[2], &e->count);
            if (!q || q != we[2] || e->count < 0)
                return cloth__io_fail(io, CLOTH_ERROR_PARSE, w[2], 1, "bad element count '%.*s'", cloth__quote_length(w[2], eol),
                                      w[2]);
            e->first_property = ply->property_count;
        } else if (cloth__bytes_are(w[0], we[0], "property")) {
            cloth__ply_property *prop = &ply->property[ply->property_count];
            if (ply->element_count == 0) return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "a property before any element");
            memset(prop, 0, sizeof *prop);
            if (n == 3) {
                prop->type = (unsigned char)cloth__ply_type(w[1], we[1]);
                if (!prop->type) return cloth__io_fail(io, CLOTH_ERROR_PARSE, w[1], 1, "unknown property type '%.*s'",
                                                       cloth__quote_length(w[1], eol), w[1]);
            } else if (n == 5 && cloth__bytes_are(w[1], we[1], "list")) {
                prop->count_type = (unsigned char)cloth__ply_type(w[2], we[2]);
                prop->type = (unsigned char)cloth__ply_type(w[3], we[3]);
                if (!cloth__type_is_integer(prop->count_type))
                    return cloth__io_fail(io, CLOTH_ERROR_PARSE, w[2], 1, "a list count type must be an integer type, not '%.*s'",
                                          cloth__quote_length(w[2], eol), w[2]);
                if (!prop->type) return cloth__io_fail(io, CLOTH_ERROR_PARSE, w[3], 1, "unknown property type '%.*s'",
                                                       cloth__quote_length(w[3], eol), w[3]);
            } else {
                return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "a property line is 'property TYPE NAME' or "
                                      "'property list COUNT_TYPE ITEM_TYPE NAME'");
            }
            /* Roles, in the vertex and face elements only. */
            {
                cloth__ply_element *e = &ply->element[ply->element_count - 1];
                const unsigned char *name = w[n - 1], *name_end = we[n - 1];
                int role = CLOTH__PLY_OTHER;
                if (cloth__bytes_are(e->name, e->name + e->name_length, "vertex")) {
                    static const char *const names[] = { "x", "y", "z", "u", "v", "s", "t", "texture_u", "texture_v" };
                    int k;
                    for (k = 0; k < 9; ++k)
                        if (cloth__bytes_are(name, name_end, names[k])) role = CLOTH__PLY_X + k;
                    if (role != CLOTH__PLY_OTHER && prop->count_type) {
                        if (role <= CLOTH__PLY_Z)
                            return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "vertex property %.*s is a list",
                                                  cloth__quote_length(name, eol), name);
                        role = CLOTH__PLY_OTHER; /* a list named u is not a texture coordinate */
                    }
                } else if (cloth__bytes_are(e->name, e->name + e->name_length, "face")) {
                    if (prop->count_type &&
                        (cloth__bytes_are(name, name_end, "vertex_indices") || cloth__bytes_are(name, name_end, "vertex_index")))
                        role = CLOTH__PLY_INDICES;
                }
                if (role != CLOTH__PLY_OTHER && ply->role[role] < 0) {
                    if (role == CLOTH__PLY_INDICES && !cloth__type_is_integer(prop->type))
                        return cloth__io_fail(io, CLOTH_ERROR_UNSUPPORTED, w[3], 1, "face indices of type '%.*s' (integers only)",
                                              cloth__quote_length(w[3], eol), w[3]);
                    ply->role[role] = ply->property_count;
                    prop->role = (unsigned char)role;
                }
            }
            ++ply->property_count;
            ++ply->element[ply->element_count - 1].property_count;
        } else {
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, w[0], 1, "unknown PLY header line '%.*s'",
                                  cloth__quote_length(w[0], eol), w[0]);
        }
    }
    if (!have_format) return cloth__io_fail(io, CLOTH_ERROR_PARSE, ply->body, 1, "the PLY header has no format line");
    for (i = 0; i < ply->element_count; ++i) {
        cloth__ply_element *e = &ply->element[i];
        int k;
        if (cloth__bytes_are(e->name, e->name + e->name_length, "vertex")) {
            if (ply->vertex >= 0) return cloth__io_fail(io, CLOTH_ERROR_PARSE, e->line, 1, "a second vertex element");
            ply->vertex = i;
        } else if (cloth__bytes_are(e->name, e->name + e->name_length, "face")) {
            if (ply->face >= 0) return cloth__io_fail(io, CLOTH_ERROR_PARSE, e->line, 1, "a second face element");
            ply->face = i;
        }
        e->stride = 0;
        for (k = 0; k < e->property_count; ++k) {
            const cloth__ply_property *prop = &ply->property[e->first_property + k];
            if (prop->count_type) { e->stride = 0; break; }
            e->stride += cloth__type_size[prop->type];
        }
    }
    if (ply->vertex < 0) return cloth__io_fail(io, CLOTH_ERROR_EMPTY_MESH, ply->body, 1, "the PLY file has no vertex element");
    for (i = CLOTH__PLY_X; i <= CLOTH__PLY_Z; ++i)
        if (ply->role[i] < 0)
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, ply->element[ply->vertex].line, 1,
                                  "the vertex element has no property %c", "xyz"[i - CLOTH__PLY_X]);
    if (ply->face >= 0 && ply->role[CLOTH__PLY_INDICES] < 0)
        return cloth__io_fail(io, CLOTH_ERROR_PARSE, ply->element[ply->face].line, 1,
                              "the face element has no list property vertex_indices (or vertex_index)");
    for (i = CLOTH__PLY_U; i <= CLOTH__PLY_TEXTURE_U; i += 2) {
        if (ply->role[i] >= 0 && ply->role[i + 1] >= 0) {
            ply->uv_u = i;
            ply->uv_v = i + 1;
            break;
        }
    }
    return CLOTH_SUCCESS;
}

/* Skip one ascii token; TRUNCATED at the end of the data. */
static cloth_result cloth__ply_ascii_skip(const cloth__ply *ply, const unsigned char **pp, const cloth__ply_element *e,
                                          int64_t item)
{
    const unsigned char *p = cloth__skip_space(*pp, ply->io->end);
    if (p >= ply->io->end)
        return cloth__io_fail(ply->io, CLOTH_ERROR_TRUNCATED, p, 1, "the data ends inside item %lld of element '%.*s'",
                              (long long)item, e->name_length, e->name);
    *pp = cloth__token_end(p, ply->io->end);
    return CLOTH_SUCCESS;
}

/* Read one ascii list length at *pp. */
static cloth_result cloth__ply_ascii_count(const cloth__ply *ply, const unsigned char **pp, const cloth__ply_element *e,
                                           int64_t item, int64_t *count)
{
    const unsigned char *end = ply->io->end, *p = cloth__skip_space(*pp, end), *q;
    if (p >= end)
        return cloth__io_fail(ply->io, CLOTH_ERROR_TRUNCATED, p, 1, "the data ends inside item %lld of element '%.*s'",
                              (long long)item, e->name_length, e->name);
    q = cloth__scan_int(p, end, count);
    if (!q || (q < end && !cloth__is_space(*q)) || *count < 0)
        return cloth__io_fail(ply->io, CLOTH_ERROR_PARSE, p, 1, "bad list length '%.*s'", cloth__quote_length(p, end), p);
    *pp = q;
    return CLOTH_SUCCESS;
}

/* First pass over the body: find where each element starts, check that every item is
   there, count the triangles. */
static cloth_result cloth__ply_walk(cloth__ply *ply)
{
    const cloth__io *io = ply->io;
    const unsigned char *p = ply->body, *end = io->end;
    const cloth__ply_element *current = NULL;
    int i, k;
    cloth_result r;
    ply->triangle_count = 0;
    ply->all_triangles = 1;
    for (i = 0; i < ply->element_count; ++i) {
        cloth__ply_element *e = &ply->element[i];
        const cloth__ply_property *props = ply->property + e->first_property;
        int64_t item;
        current = e;
        e->data = p;
        if (e->count == 0 || e->property_count == 0) continue;
        if (ply->binary && e->stride) {
            if ((uint64_t)e->count > (uint64_t)(end - p) / e->stride)
                return cloth__io_fail(io, CLOTH_ERROR_TRUNCATED, p, 0,
                                      "element '%.*s' announces %lld items of %lu bytes; %lu bytes remain", e->name_length,
                                      e->name, (long long)e->count, (unsigned long)e->stride, (unsigned long)(end - p));
            p += (size_t)e->count * e->stride;
            continue;
        }
        for (item = 0; item < e->count; ++item) {
            for (k = 0; k < e->property_count; ++k) {
                const cloth__ply_property *prop = &props[k];
                int64_t count = 0, j;
                if (ply->binary) {
                    size_t size = cloth__type_size[prop->type], csize = cloth__type_size[prop->count_type];
                    if (!prop->count_type) {
                        if ((size_t)(end - p) < size) goto truncated;
                        p += size;
                        continue;
                    }
                    if ((size_t)(end - p) < csize) goto truncated;
                    count = cloth__load_int(p, prop->count_type, ply->big_endian);
                    if (count < 0)
                        return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 0, "negative list length %lld", (long long)count);
                    p += csize;
                    if ((uint64_t)count > (uint64_t)(end - p) / size) goto truncated;
                    p += (size_t)count * size;
                } else {
                    if (!prop->count_type) {
                        if ((r = cloth__ply_ascii_skip(ply, &p, e, item)) != CLOTH_SUCCESS) return r;
                        continue;
                    }
                    if ((r = cloth__ply_ascii_count(ply, &p, e, item, &count)) != CLOTH_SUCCESS) return r;
                    for (j = 0; j < count; ++j)
                        if ((r = cloth__ply_ascii_skip(ply, &p, e, item)) != CLOTH_SUCCESS) return r;
                }
                if (prop->role == CLOTH__PLY_INDICES) {
                    if (count < 3)
                        return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, !ply->binary,
                                              "face %lld has %lld vertices (at least 3 needed)", (long long)item,
                                              (long long)count);
                    ply->triangle_count += count - 2;
                    ply->all_triangles &= count == 3;
                }
            }
        }
    }
    return CLOTH_SUCCESS;
truncated:
    return cloth__io_fail(io, CLOTH_ERROR_TRUNCATED, p, 0, "the data ends inside element '%.*s'", current->name_length,
                          current->name);
}

/* Where the value of a vertex property with `role` goes, NULL when it is not read. */
static cloth_real *cloth__ply_slot(const cloth__ply *ply, cloth_mesh *mesh, int role, int64_t vertex)
{
    if (role >= CLOTH__PLY_X && role <= CLOTH__PLY_Z) return mesh->x + 3 * vertex + (role - CLOTH__PLY_X);
    if (mesh->uv && role == ply->uv_u) return mesh->uv + 2 * vertex;
    if (mesh->uv && role == ply->uv_v) return mesh->uv + 2 * vertex + 1;
    return NULL;
}

static cloth_result cloth__ply_store(const cloth__ply *ply, cloth_real *slot, double value, const unsigned char *at,
                                     int64_t vertex)
{
    *slot = (cloth_real)value;
    if (!cloth__is_finite(*slot))
        return cloth__io_fail(ply->io, CLOTH_ERROR_NOT_FINITE, at, !ply->binary, "vertex %lld: a coordinate is not finite (%g)",
                              (long long)vertex, value);
    return CLOTH_SUCCESS;
}

static cloth_result cloth__ply_read_vertices(const cloth__ply *ply, cloth_mesh *mesh)
{
    const cloth__io *io = ply->io;
    const cloth__ply_element *e = &ply->element[ply->vertex];
    const cloth__ply_property *props = ply->property + e->first_property;
    const unsigned char *p = e->data, *end = io->end;
    int64_t i;
    int k;
    cloth_result r;
    if (ply->binary && e->stride) {
        /* Fixed stride: every property at a fixed offset in the item. */
        size_t offset[5];
        int type[5], count = 0, role[5];
        size_t at = 0;
        for (k = 0; k < e->property_count; ++k) {
            int rk = props[k].role;
            if (rk != CLOTH__PLY_OTHER && cloth__ply_slot(ply, mesh, rk, 0) != NULL) {
                offset[count] = at;
                type[count] = props[k].type;
                role[count++] = rk;
            }
            at += cloth__type_size[props[k].type];
        }
        for (i = 0; i < e->count; ++i, p += e->stride) {
            for (k = 0; k < count; ++k) {
                double value = cloth__load_real(p + offset[k], type[k], ply->big_endian);
                r = cloth__ply_store(ply, cloth__ply_slot(ply, mesh, role[k], i), value, p + offset[k], i);
                if (r != CLOTH_SUCCESS) return r;
            }
        }
        return CLOTH_SUCCESS;
    }
    for (i = 0; i < e->count; ++i) {
        for (k = 0; k < e->property_count; ++k) {
            const cloth__ply_property *prop = &props[k];
            cloth_real *slot = prop->count_type ? NULL : cloth__ply_slot(ply, mesh, prop->role, i);
            if (ply->binary) {
                size_t size = cloth__type_size[prop->type];
                if (prop->count_type) {
                    int64_t count = cloth__load_int(p, prop->count_type, ply->big_endian);
                    p += cloth__type_size[prop->count_type] + (size_t)count * size;
                } else {
                    if (slot) {
                        r = cloth__ply_store(ply, slot, cloth__load_real(p, prop->type, ply->big_endian), p, i);
                        if (r != CLOTH_SUCCESS) return r;
                    }
                    p += size;
                }
            } else if (prop->count_type) {
                int64_t count = 0, j;
                if ((r = cloth__ply_ascii_count(ply, &p, e, i, &count)) != CLOTH_SUCCESS) return r;
                for (j = 0; j < count; ++j)
                    if ((r = cloth__ply_ascii_skip(ply, &p, e, i)) != CLOTH_SUCCESS) return r;
            } else if (slot) {
                double value = 0;
                const unsigned char *q;
                p = cloth__skip_space(p, end);
                q = cloth__scan_double(p, end, &value);
                if (!q || (q < end && !cloth__is_space(*q)))
                    return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "vertex %lld: '%.*s' is not a number", (long long)i,
                                          cloth__quote_length(p, end), p);
                if ((r = cloth__ply_store(ply, slot, value, p, i)) != CLOTH_SUCCESS) return r;
                p = q;
            } else if ((r = cloth__ply_ascii_skip(ply, &p, e, i)) != CLOTH_SUCCESS) {
                return r;
            }
        }
    }
    return CLOTH_SUCCESS;
}

/* One face index of a binary or ascii file into *index, checked against the vertex count. */
static cloth_result cloth__ply_index(const cloth__ply *ply, const unsigned char **pp, int type, int64_t face, int32_t *index)
{
    const cloth__io *io = ply->io;
    const unsigned char *p = *pp, *end = io->end;
    int64_t v = 0;
    int64_t vertex_count = ply->element[ply->vertex].count;
    if (ply->binary) {
        v = cloth__load_int(p, type, ply->big_endian);
        *pp = p + cloth__type_size[type];
    } else {
        const unsigned char *q;
        p = cloth__skip_space(p, end);
        q = cloth__scan_int(p, end, &v);
        if (!q || (q < end && !cloth__is_space(*q)))
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "face %lld: '%.*s' is not a vertex index", (long long)face,
                                  cloth__quote_length(p, end), p);
        *pp = q;
    }
    if (v < 0 || v >= vertex_count)
        return cloth__io_fail(io, CLOTH_ERROR_INDEX_OUT_OF_RANGE, p, !ply->binary, "face %lld names vertex %lld of %lld",
                              (long long)face, (long long)v, (long long)vertex_count);
    *index = (int32_t)v;
    return CLOTH_SUCCESS;
}

static cloth_result cloth__ply_read_faces(const cloth__ply *ply, cloth_mesh *mesh)
{
    const cloth__ply_element *e = &ply->element[ply->face];
    const cloth__ply_property *props = ply->property + e->first_property;
    const unsigned char *p = e->data;
    int32_t *tri = mesh->tri, *tri_end = mesh->tri + 3 * (size_t)mesh->triangle_count;
    int64_t f;
    int k;
    cloth_result r;
    if (ply->binary && ply->all_triangles && e->property_count == 1) {
        /* Fixed stride: a count and three indices per face. */
        int type = props[0].type;
        size_t csize = cloth__type_size[props[0].count_type];
        for (f = 0; f < e->count; ++f) {
            p += csize;
            if ((r = cloth__ply_index(ply, &p, type, f, tri)) != CLOTH_SUCCESS) return r;
            if ((r = cloth__ply_index(ply, &p, type, f, tri + 1)) != CLOTH_SUCCESS) return r;
            if ((r = cloth__ply_index(ply, &p, type, f, tri + 2)) != CLOTH_SUCCESS) return r;
            tri += 3;
        }
        return CLOTH_SUCCESS;
    }
    for (f = 0; f < e->count; ++f) {
        for (k = 0; k < e->property_count; ++k) {
            const cloth__ply_property *prop = &props[k];
            int64_t count = 0, j;
            if (!prop->count_type) {
                if (ply->binary) p += cloth__type_size[prop->type];
                else if ((r = cloth__ply_ascii_skip(ply, &p, e, f)) != CLOTH_SUCCESS) return r;
                continue;
            }
            if (ply->binary) {
                count = cloth__load_int(p, prop->count_type, ply->big_endian);
                p += cloth__type_size[prop->count_type];
            } else if ((r = cloth__ply_ascii_count(ply, &p, e, f, &count)) != CLOTH_SUCCESS) {
                return r;
            }
            if (prop->role != CLOTH__PLY_INDICES) {
                if (ply->binary) {
                    p += (size_t)count * cloth__type_size[prop->type];
                } else {
                    for (j = 0; j < count; ++j)
                        if ((r = cloth__ply_ascii_skip(ply, &p, e, f)) != CLOTH_SUCCESS) return r;
                }
                continue;
            }
            {
                int32_t first = 0, previous = 0, v = 0;
                for (j = 0; j < count; ++j) {
                    if ((r = cloth__ply_index(ply, &p, prop->type, f, &v)) != CLOTH_SUCCESS) return r;
                    if (j == 0) first = v;
                    if (j >= 2 && tri < tri_end) {
                        tri[0] = first;
                        tri[1] = previous;
                        tri[2] = v;
                        tri += 3;
                    }
                    previous = v;
                }
            }
        }
    }
    return CLOTH_SUCCESS;
}

static cloth_result cloth__read_ply(const cloth__io *io, cloth_mesh *mesh)
{
    cloth__ply ply;
    cloth_result r;
    int i;
    memset(&ply, 0, sizeof ply);
    ply.io = io;
    ply.vertex = ply.face = -1;
    for (i = 0; i < CLOTH__PLY_ROLE_COUNT; ++i) ply.role[i] = -1;
    r = cloth__ply_header(&ply);
    if (r == CLOTH_SUCCESS) r = cloth__ply_walk(&ply);
    if (r == CLOTH_SUCCESS)
        r = cloth__io_mesh_alloc(io, mesh, ply.element[ply.vertex].count, ply.triangle_count, ply.uv_u != 0, !ply.binary);
    if (r == CLOTH_SUCCESS) r = cloth__ply_read_vertices(&ply, mesh);
    if (r == CLOTH_SUCCESS) r = cloth__ply_read_faces(&ply, mesh);
    cloth__free(&io->allocator, ply.element);
    cloth__free(&io->allocator, ply.property);
    return r;
}

/* ---- VTK legacy ------------------------------------------------------------------------ */

typedef struct cloth__vtk {
    const cloth__io *io;
    const unsigned char *p; /* the cursor */
    int binary;
    int dataset;            /* 1 UNSTRUCTURED_GRID, 2 POLYDATA */
    int64_t point_count;    /* -1 before POINTS */
    cloth_real *points;
    int64_t cell_count;     /* -1 before CELLS (or POLYGONS) */
    int64_t *offsets;       /* cell_count + 1: cell c is connectivity[offsets[c] .. offsets[c+1]) */
    int32_t *connectivity;
    int64_t type_count;     /* -1 before CELL_TYPES */
    int32_t *types;
    const unsigned char *types_at;
} cloth__vtk;

static cloth__type cloth__vtk_type(const unsigned char *p, const unsigned char *e)
{
    static const struct { const char *name; cloth__type type; } names[] = {
        { "unsigned_char", CLOTH__TYPE_UINT8 }, { "char", CLOTH__TYPE_INT8 }, { "unsigned_short", CLOTH__TYPE_UINT16 },
        { "short", CLOTH__TYPE_INT16 }, { "unsigned_int", CLOTH__TYPE_UINT32 }, { "int", CLOTH__TYPE_INT32 },
        { "unsigned_long", CLOTH__TYPE_UINT64 }, { "long", CLOTH__TYPE_INT64 }, { "float", CLOTH__TYPE_FLOAT32 },
        { "double", CLOTH__TYPE_FLOAT64 }, { "vtkIdType", CLOTH__TYPE_INT64 }, { "vtktypeint8", CLOTH__TYPE_INT8 },
        { "vtktypeuint8", CLOTH__TYPE_UINT8 }, { "vtktypeint16", CLOTH__TYPE_INT16 }, { "vtktypeuint16", CLOTH__TYPE_UINT16 },
        { "vtktypeint32", CLOTH__TYPE_INT32 }, { "vtktypeuint32", CLOTH__TYPE_UINT32 }, { "vtktypeint64", CLOTH__TYPE_INT64 },
        { "vtktypeuint64", CLOTH__TYPE_UINT64 }, { "vtktypefloat32", CLOTH__TYPE_FLOAT32 },
        { "vtktypefloat64", CLOTH__TYPE_FLOAT64 }
    };
    size_t i;
    for (i = 0; i < sizeof names / sizeof names[0]; ++i)
        if (cloth__token_is(p, e, names[i].name)) return names[i].type;
    return CLOTH__TYPE_NONE;
}

/* The words of the next line that is not blank (at most `max`, their number returned, 0 at
   the end of the data); the cursor moves past its line break, where binary data starts. */
static int cloth__vtk_line(cloth__vtk *v, const unsigned char **w, const unsigned char **we, int max)
{
    const unsigned char *end = v->io->end;
    while (v->p < end) {
        const unsigned char *p = v->p, *eol = cloth__line_end(p, end);
        int n;
        v->p = eol < end ? eol + 1 : end;
        n = cloth__split_line(p, eol, w, we, max);
        if (n > 0) return n;
    }
    return 0;
}

/* A count from a keyword line. */
static cloth_result cloth__vtk_count(const cloth__vtk *v, const unsigned char *w, const unsigned char *we, int64_t *out)
{
    const unsigned char *q = cloth__scan_int(w, we, out);
    if (!q || q != we || *out < 0)
        return cloth__io_fail(v->io, CLOTH_ERROR_PARSE, w, 1, "bad count '%.*s'", cloth__quote_length(w, we), w);
    return CLOTH_SUCCESS;
}

/* A data type from a keyword line; CLOTH_ERROR_UNSUPPORTED for bit and string data. */
static cloth_result cloth__vtk_data_type(const cloth__vtk *v, const unsigned char *w, const unsigned char *we, int integer,
                                         int *type)
{
    *type = cloth__vtk_type(w, we);
    if (!*type)
        return cloth__io_fail(v->io, CLOTH_ERROR_UNSUPPORTED, w, 1, "VTK data type '%.*s'", cloth__quote_length(w, we), w);
    if (integer && !cloth__type_is_integer(*type))
        return cloth__io_fail(v->io, CLOTH_ERROR_PARSE, w, 1, "cell data of type '%.*s' (integers needed)",
                              cloth__quote_length(w, we), w);
    return CLOTH_SUCCESS;
}

/* Whether `count` values of `type` can follow the cursor at all: each takes its size in
   binary and at least two bytes (but the last) in ascii. Checked before any allocation. */
static cloth_result cloth__vtk_fits(const cloth__vtk *v, int64_t count, int type, const char *what)
{
    uint64_t remaining = (uint64_t)(v->io->end - v->p), per = v->binary ? cloth__type_size[type] : 2;
    if ((uint64_t)count > (remaining + 1) / per)
        return cloth__io_fail(v->io, CLOTH_ERROR_TRUNCATED, v->p, !v->binary, "%s: %lld values announced, only %llu bytes remain",
                              what, (long long)count, (unsigned long long)remaining);
    return CLOTH_SUCCESS;
}

/* The next value at the cursor as a double (real) or an integer; *at is where it starts. */
static cloth_result cloth__vtk_value(cloth__vtk *v, int type, int integer, double *real, int64_t *whole, const unsigned char **at)
{
    const unsigned char *end = v->io->end, *p = v->p, *q;
    if (v->binary) {
        size_t size = cloth__type_size[type];
        if ((size_t)(end - p) < size) return cloth__io_fail(v->io, CLOTH_ERROR_TRUNCATED, p, 0, "the data ends inside an array");
        if (integer) *whole = cloth__load_int(p, type, 1);
        else *real = cloth__load_real(p, type, 1);
        *at = p;
        v->p = p + size;
        return CLOTH_SUCCESS;
    }
    p = cloth__skip_space(p, end);
    if (p >= end) return cloth__io_fail(v->io, CLOTH_ERROR_TRUNCATED, p, 1, "the data ends inside an array");
    q = integer ? cloth__scan_int(p, end, whole) : cloth__scan_double(p, end, real);
    if (!q || (q < end && !cloth__is_space(*q)))
        return cloth__io_fail(v->io, CLOTH_ERROR_PARSE, p, 1, "'%.*s' is not %s", cloth__quote_length(p, end), p,
                              integer ? "an integer" : "a number");
    *at = p;
    v->p = q;
    return CLOTH_SUCCESS;
}

/* Skip `count` values of `type` (already checked with cloth__vtk_fits). */
static cloth_result cloth__vtk_skip(cloth__vtk *v, int64_t count, int type)
{
    const unsigned char *end = v->io->end;
    int64_t i;
    if (v->binary) {
        if ((uint64_t)count > (uint64_t)(end - v->p) / cloth__type_size[type])
            return cloth__io_fail(v->io, CLOTH_ERROR_TRUNCATED, v->p, 0, "the data ends inside an array");
        v->p += (size_t)count * cloth__type_size[type];
        return CLOTH_SUCCESS;
    }
    for (i = 0; i < count; ++i) {
        const unsigned char *p = cloth__skip_space(v->p, end);
        if (p >= end) return cloth__io_fail(v->io, CLOTH_ERROR_TRUNCATED, p, 1, "the data ends inside an array");
        v->p = cloth__token_end(p, end);
    }
    return CLOTH_SUCCESS;
}

/* Skip a METADATA block: lines up to the first blank one. */
static void cloth__vtk_skip_metadata(cloth__vtk *v)
{
    const unsigned char *end = v->io->end;
    while (v->p < end) {
        const unsigned char *p = v->p, *eol = cloth__line_end(p, end);
        v->p = eol < end ? eol + 1 : end;
        if (cloth__skip_blank(p, eol) == eol) break;
    }
}

/* FIELD name count: skip its arrays. */
static cloth_result cloth__vtk_skip_field(cloth__vtk *v, int64_t arrays)
{
    const unsigned char *w[6], *we[6];
    int64_t a;
    cloth_result r;
    for (a = 0; a < arrays; ++a) {
        int64_t components = 0, tuples = 0;
        int n = cloth__vtk_line(v, w, we, 6), type = 0;
        if (n == 0) return cloth__io_fail(v->io, CLOTH_ERROR_TRUNCATED, v->p, 1, "the data ends inside FIELD data");
        if (cloth__token_is(w[0], we[0], "METADATA")) {
            cloth__vtk_skip_metadata(v);
            --a;
            continue;
        }
        if (cloth__token_is(w[0], we[0], "NULL_ARRAY")) continue;
        if (n != 4) return cloth__io_fail(v->io, CLOTH_ERROR_PARSE, w[0], 1, "a FIELD array is 'NAME COMPONENTS TUPLES TYPE'");
        if ((r = cloth__vtk_count(v, w[1], we[1], &components)) != CLOTH_SUCCESS) return r;
        if ((r = cloth__vtk_count(v, w[2], we[2], &tuples)) != CLOTH_SUCCESS) return r;
        if ((r = cloth__vtk_data_type(v, w[3], we[3], 0, &type)) != CLOTH_SUCCESS) return r;
        if (components > INT32_MAX || tuples > INT32_MAX) return cloth__vtk_fits(v, INT64_MAX, type, "FIELD array");
        if ((r = cloth__vtk_fits(v, components * tuples, type, "FIELD array")) != CLOTH_SUCCESS) return r;
        if ((r = cloth__vtk_skip(v, components * tuples, type)) != CLOTH_SUCCESS) return r;
    }
    return CLOTH_SUCCESS;
}

static cloth_result cloth__vtk_points(cloth__vtk *v, int64_t count, int type)
{
    const cloth__io *io = v->io;
    int64_t i;
    cloth_result r;
    if (count > INT32_MAX) return cloth__vtk_fits(v, INT64_MAX, type, "POINTS");
    if ((r = cloth__vtk_fits(v, 3 * count, type, "POINTS")) != CLOTH_SUCCESS) return r;
    v->points = (cloth_real *)cloth__alloc_array(&io->allocator, (size_t)(3 * count), sizeof(cloth_real));
    if (!v->points)
        return cloth__io_fail(io, CLOTH_ERROR_OUT_OF_MEMORY, NULL, 0, "cannot allocate %lld points", (long long)count);
    for (i = 0; i < 3 * count; ++i) {
        double value = 0;
        int64_t unused = 0;
        const unsigned char *at = NULL;
        if ((r = cloth__vtk_value(v, type, 0, &value, &unused, &at)) != CLOTH_SUCCESS) return r;
        v->points[i] = (cloth_real)value;
        if (!cloth__is_finite(v->points[i]))
            return cloth__io_fail(io, CLOTH_ERROR_NOT_FINITE, at, !v->binary, "point %lld: a coordinate is not finite (%g)",
                                  (long long)(i / 3), value);
    }
    v->point_count = count;
    return CLOTH_SUCCESS;
}

/* One vertex index of a cell, checked against the points. */
static cloth_result cloth__vtk_index(cloth__vtk *v, int type, int64_t cell, int32_t *out)
{
    int64_t index = 0;
    double unused = 0;
    const unsigned char *at = NULL;
    cloth_result r = cloth__vtk_value(v, type, 1, &unused, &index, &at);
    if (r != CLOTH_SUCCESS) return r;
    if (index < 0 || index >= v->point_count)
        return cloth__io_fail(v->io, CLOTH_ERROR_INDEX_OUT_OF_RANGE, at, !v->binary, "cell %lld names point %lld of %lld",
                              (long long)cell, (long long)index, (long long)v->point_count);
    *out = (int32_t)index;
    return CLOTH_SUCCESS;
}

/* A cell array after its keyword line "KEYWORD n size": the classic layout (a count before
   each cell's indices, int32 in binary) or, when OFFSETS follows, the version 5.1 layout
   (n offsets, then size connectivity entries). Every index is checked. */
static cloth_result cloth__vtk_cells(cloth__vtk *v, int64_t n, int64_t size, int64_t *cell_count, int64_t **offsets,
                                     int32_t **connectivity)
{
    const cloth__io *io = v->io;
    const unsigned char *w[4], *we[4], *q = cloth__skip_space(v->p, io->end);
    int64_t c, i;
    cloth_result r;
    if (v->point_count < 0) return cloth__io_fail(io, CLOTH_ERROR_PARSE, v->p, 1, "cells before POINTS");
    if (cloth__starts_with(q, io->end, "OFFSETS")) {
        int type = 0;
        int64_t count = n > 0 ? n - 1 : 0, previous = 0, value = 0;
        double unused = 0;
        const unsigned char *at = NULL;
        if (cloth__vtk_line(v, w, we, 4) != 2) return cloth__io_fail(io, CLOTH_ERROR_PARSE, q, 1, "expected 'OFFSETS TYPE'");
        if ((r = cloth__vtk_data_type(v, w[1], we[1], 1, &type)) != CLOTH_SUCCESS) return r;
        if ((r = cloth__vtk_fits(v, n, type, "OFFSETS")) != CLOTH_SUCCESS) return r;
        if (size > INT32_MAX) return cloth__vtk_fits(v, INT64_MAX, type, "CONNECTIVITY");
        if ((r = cloth__vtk_fits(v, size, type, "CONNECTIVITY")) != CLOTH_SUCCESS) return r;
        *offsets = (int64_t *)cloth__alloc_array(&io->allocator, (size_t)count + 1, sizeof(int64_t));
        *connectivity = (int32_t *)cloth__alloc_array(&io->allocator, (size_t)size, sizeof(int32_t));
        if (!*offsets || !*connectivity)
            return cloth__io_fail(io, CLOTH_ERROR_OUT_OF_MEMORY, NULL, 0, "cannot allocate the cells");
        (*offsets)[0] = 0;
        for (i = 0; i < n; ++i) {
            if ((r = cloth__vtk_value(v, type, 1, &unused, &value, &at)) != CLOTH_SUCCESS) return r;
            if ((i == 0 && value != 0) || value < previous || value > size)
                return cloth__io_fail(io, CLOTH_ERROR_PARSE, at, !v->binary,
                                      "offset %lld is %lld: offsets start at 0 and grow up to the connectivity size %lld",
                                      (long long)i, (long long)value, (long long)size);
            (*offsets)[i] = value;
            previous = value;
        }
        if (previous != size)
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, v->p, !v->binary,
                                  "the last offset is %lld, not the connectivity size %lld", (long long)previous,
                                  (long long)size);
        if (cloth__vtk_line(v, w, we, 4) != 2 || !cloth__token_is(w[0], we[0], "CONNECTIVITY"))
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, v->p, 1, "expected 'CONNECTIVITY TYPE' after the offsets");
        if ((r = cloth__vtk_data_type(v, w[1], we[1], 1, &type)) != CLOTH_SUCCESS) return r;
        if ((r = cloth__vtk_fits(v, size, type, "CONNECTIVITY")) != CLOTH_SUCCESS) return r;
        for (c = 0; c < count; ++c)
            for (i = (*offsets)[c]; i < (*offsets)[c + 1]; ++i)
                if ((r = cloth__vtk_index(v, type, c, *connectivity + i)) != CLOTH_SUCCESS) return r;
        *cell_count = count;
        return CLOTH_SUCCESS;
    }
    /* Classic: n cells in size values, each a count and that many indices. */
    if (n > size)
        return cloth__io_fail(io, CLOTH_ERROR_PARSE, v->p, 1, "%lld cells cannot fit in %lld values", (long long)n,
                              (long long)size);
    if (size > INT32_MAX) return cloth__vtk_fits(v, INT64_MAX, CLOTH__TYPE_INT32, "CELLS");
    if ((r = cloth__vtk_fits(v, size, CLOTH__TYPE_INT32, "CELLS")) != CLOTH_SUCCESS) return r;
    *offsets = (int64_t *)cloth__alloc_array(&io->allocator, (size_t)n + 1, sizeof(int64_t));
    *connectivity = (int32_t *)cloth__alloc_array(&io->allocator, (size_t)(size - n), sizeof(int32_t));
    if (!*offsets || !*connectivity) return cloth__io_fail(io, CLOTH_ERROR_OUT_OF_MEMORY, NULL, 0, "cannot allocate the cells");
    for (c = 0, i = 0; c < n; ++c) {
        int64_t k = 0;
        double unused = 0;
        const unsigned char *at = NULL;
        if ((r = cloth__vtk_value(v, CLOTH__TYPE_INT32, 1, &unused, &k, &at)) != CLOTH_SUCCESS) return r;
        if (k < 0 || k > size - n - i)
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, at, !v->binary,
                                  "cell %lld has %lld points, more than the cell data holds", (long long)c, (long long)k);
        (*offsets)[c] = i;
        for (; k > 0; --k, ++i)
            if ((r = cloth__vtk_index(v, CLOTH__TYPE_INT32, c, *connectivity + i)) != CLOTH_SUCCESS) return r;
    }
    (*offsets)[n] = i;
    if (i != size - n)
        return cloth__io_fail(io, CLOTH_ERROR_PARSE, v->p, !v->binary, "the cells hold %lld values, the header says %lld",
                              (long long)(i + n), (long long)size);
    *cell_count = n;
    return CLOTH_SUCCESS;
}

/* The keyword loop: everything up to the first attribute section or the end of the data. */
static cloth_result cloth__vtk_sections(cloth__vtk *v)
{
    const cloth__io *io = v->io;
    const unsigned char *w[6], *we[6];
    cloth_result r;
    int n;
    while ((n = cloth__vtk_line(v, w, we, 6)) > 0) {
        const unsigned char *k = w[0], *ke = we[0];
        int64_t a = 0, b = 0;
        int type = 0;
        if (cloth__token_is(k, ke, "DATASET")) {
            if (v->dataset) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "a second DATASET");
            if (n != 2) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "expected 'DATASET TYPE'");
            if (cloth__token_is(w[1], we[1], "UNSTRUCTURED_GRID")) v->dataset = 1;
            else if (cloth__token_is(w[1], we[1], "POLYDATA")) v->dataset = 2;
            else if (cloth__token_is(w[1], we[1], "STRUCTURED_POINTS") || cloth__token_is(w[1], we[1], "STRUCTURED_GRID") ||
                     cloth__token_is(w[1], we[1], "RECTILINEAR_GRID") || cloth__token_is(w[1], we[1], "FIELD"))
                return cloth__io_fail(io, CLOTH_ERROR_UNSUPPORTED, w[1], 1,
                                      "VTK dataset %.*s (only UNSTRUCTURED_GRID and POLYDATA are read)",
                                      cloth__quote_length(w[1], we[1]), w[1]);
            else
                return cloth__io_fail(io, CLOTH_ERROR_PARSE, w[1], 1, "unknown VTK dataset '%.*s'",
                                      cloth__quote_length(w[1], we[1]), w[1]);
        } else if (cloth__token_is(k, ke, "FIELD")) {
            if (n != 3) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "expected 'FIELD NAME ARRAYS'");
            if ((r = cloth__vtk_count(v, w[2], we[2], &a)) != CLOTH_SUCCESS) return r;
            if ((r = cloth__vtk_skip_field(v, a)) != CLOTH_SUCCESS) return r;
        } else if (cloth__token_is(k, ke, "METADATA")) {
            cloth__vtk_skip_metadata(v);
        } else if (cloth__token_is(k, ke, "POINT_DATA") || cloth__token_is(k, ke, "CELL_DATA")) {
            break; /* attributes: nothing more of the geometry follows */
        } else if (!v->dataset) {
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "'%.*s' before the DATASET line", cloth__quote_length(k, ke), k);
        } else if (cloth__token_is(k, ke, "POINTS")) {
            if (v->point_count >= 0) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "a second POINTS section");
            if (n != 3) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "expected 'POINTS COUNT TYPE'");
            if ((r = cloth__vtk_count(v, w[1], we[1], &a)) != CLOTH_SUCCESS) return r;
            if ((r = cloth__vtk_data_type(v, w[2], we[2], 0, &type)) != CLOTH_SUCCESS) return r;
            if ((r = cloth__vtk_points(v, a, type)) != CLOTH_SUCCESS) return r;
        } else if ((v->dataset == 1 && cloth__token_is(k, ke, "CELLS")) ||
                   (v->dataset == 2 && cloth__token_is(k, ke, "POLYGONS"))) {
            if (v->cell_count >= 0) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "a second %.*s section", (int)(ke - k), k);
            if (n != 3) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "expected '%.*s COUNT SIZE'", (int)(ke - k), k);
            if ((r = cloth__vtk_count(v, w[1], we[1], &a)) != CLOTH_SUCCESS) return r;
            if ((r = cloth__vtk_count(v, w[2], we[2], &b)) != CLOTH_SUCCESS) return r;
            if ((r = cloth__vtk_cells(v, a, b, &v->cell_count, &v->offsets, &v->connectivity)) != CLOTH_SUCCESS) return r;
        } else if (v->dataset == 2 && (cloth__token_is(k, ke, "VERTICES") || cloth__token_is(k, ke, "LINES") ||
                                       cloth__token_is(k, ke, "TRIANGLE_STRIPS"))) {
            int64_t count = 0, *offsets = NULL;
            int32_t *connectivity = NULL;
            if (n != 3) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "expected '%.*s COUNT SIZE'", (int)(ke - k), k);
            if ((r = cloth__vtk_count(v, w[1], we[1], &a)) != CLOTH_SUCCESS) return r;
            if ((r = cloth__vtk_count(v, w[2], we[2], &b)) != CLOTH_SUCCESS) return r;
            r = cloth__vtk_cells(v, a, b, &count, &offsets, &connectivity);
            cloth__free(&io->allocator, offsets);
            cloth__free(&io->allocator, connectivity);
            if (r != CLOTH_SUCCESS) return r;
        } else if (v->dataset == 1 && cloth__token_is(k, ke, "CELL_TYPES")) {
            int64_t i;
            if (v->type_count >= 0) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "a second CELL_TYPES section");
            if (v->cell_count < 0) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "CELL_TYPES before CELLS");
            if (n != 2) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "expected 'CELL_TYPES COUNT'");
            if ((r = cloth__vtk_count(v, w[1], we[1], &a)) != CLOTH_SUCCESS) return r;
            if (a != v->cell_count)
                return cloth__io_fail(io, CLOTH_ERROR_PARSE, w[1], 1, "%lld cell types for %lld cells", (long long)a,
                                      (long long)v->cell_count);
            if ((r = cloth__vtk_fits(v, a, CLOTH__TYPE_INT32, "CELL_TYPES")) != CLOTH_SUCCESS) return r;
            v->types = (int32_t *)cloth__alloc_array(&io->allocator, (size_t)a, sizeof(int32_t));
            if (!v->types) return cloth__io_fail(io, CLOTH_ERROR_OUT_OF_MEMORY, NULL, 0, "cannot allocate the cell types");
            v->types_at = cloth__skip_space(v->p, io->end);
            for (i = 0; i < a; ++i) {
                int64_t t = 0;
                double unused = 0;
                const unsigned char *at = NULL;
                if ((r = cloth__vtk_value(v, CLOTH__TYPE_INT32, 1, &unused, &t, &at)) != CLOTH_SUCCESS) return r;
                v->types[i] = t < 0 || t > 1000 ? -1 : (int32_t)t;
            }
            v->type_count = a;
        } else {
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "unknown VTK keyword '%.*s'", cloth__quote_length(k, ke), k);
        }
    }
    return CLOTH_SUCCESS;
}

static cloth_result cloth__read_vtk(const cloth__io *io, cloth_mesh *mesh)
{
    cloth__vtk v;
    const unsigned char *w[4], *we[4], *end = io->end, *eol;
    cloth_result r = CLOTH_SUCCESS;
    int64_t c, triangles = 0;
    int n;
    memset(&v, 0, sizeof v);
    v.io = io;
    v.point_count = v.cell_count = v.type_count = -1;
    /* "# vtk DataFile Version x.y", a title line, ASCII or BINARY */
    v.p = io->begin;
    eol = cloth__line_end(v.p, end);
    if (!cloth__starts_with(cloth__skip_blank(v.p, eol), eol, "# vtk DataFile"))
        return cloth__io_fail(io, CLOTH_ERROR_PARSE, v.p, 1,
                              "not a VTK legacy file: the first line is not '# vtk DataFile Version ...'");
    if (eol >= end) return cloth__io_fail(io, CLOTH_ERROR_TRUNCATED, end, 1, "the VTK header ends after its first line");
    eol = cloth__line_end(eol + 1, end);
    if (eol >= end) return cloth__io_fail(io, CLOTH_ERROR_TRUNCATED, end, 1, "the VTK header ends after its title line");
    v.p = eol + 1;
    eol = cloth__line_end(v.p, end);
    n = cloth__split_line(v.p, eol, w, we, 4);
    if (n == 1 && cloth__token_is(w[0], we[0], "ASCII")) v.binary = 0;
    else if (n == 1 && cloth__token_is(w[0], we[0], "BINARY")) v.binary = 1;
    else return cloth__io_fail(io, CLOTH_ERROR_PARSE, v.p, 1, "the third line of a VTK file must be ASCII or BINARY");
    v.p = eol < end ? eol + 1 : end;

    r = cloth__vtk_sections(&v);
    if (r == CLOTH_SUCCESS && !v.dataset) r = cloth__io_fail(io, CLOTH_ERROR_PARSE, v.p, 1, "the VTK file has no DATASET line");
    if (r == CLOTH_SUCCESS && v.point_count < 0)
        r = cloth__io_fail(io, CLOTH_ERROR_EMPTY_MESH, v.p, 1, "the VTK file has no POINTS");
    if (r == CLOTH_SUCCESS && v.dataset == 1 && v.cell_count >= 0 && v.type_count < 0)
        r = cloth__io_fail(io, CLOTH_ERROR_PARSE, v.p, 1, "CELLS without CELL_TYPES");
    /* Count the triangles the cells make. */
    for (c = 0; r == CLOTH_SUCCESS && c < (v.cell_count > 0 ? v.cell_count : 0); ++c) {
        int64_t k = v.offsets[c + 1] - v.offsets[c];
        int type = v.dataset == 2 ? 7 : v.types[c];
        if ((type == 5 && k != 3) || (type == 9 && k != 4) || (type == 7 && k < 3))
            r = cloth__io_fail(io, CLOTH_ERROR_PARSE, v.types_at, !v.binary, "cell %lld of type %d has %lld points", (long long)c,
                               type, (long long)k);
        else if (type == 5 || type == 9 || type == 7)
            triangles += k - 2;
    }
    if (r == CLOTH_SUCCESS) r = cloth__io_mesh_alloc(io, mesh, v.point_count, triangles, 0, !v.binary);
    if (r == CLOTH_SUCCESS) {
        int32_t *tri = mesh->tri;
        memcpy(mesh->x, v.points, sizeof(cloth_real) * 3 * (size_t)v.point_count);
        for (c = 0; c < v.cell_count; ++c) {
            int type = v.dataset == 2 ? 7 : v.types[c];
            const int32_t *cell = v.connectivity + v.offsets[c];
            int64_t k = v.offsets[c + 1] - v.offsets[c], j;
            if (type != 5 && type != 9 && type != 7) continue;
            for (j = 2; j < k; ++j) {
                tri[0] = cell[0];
                tri[1] = cell[j - 1];
                tri[2] = cell[j];
                tri += 3;
            }
        }
    }
    cloth__free(&io->allocator, v.points);
    cloth__free(&io->allocator, v.offsets);
    cloth__free(&io->allocator, v.connectivity);
    cloth__free(&io->allocator, v.types);
    return r;
}

/* ---- OFF ----------------------------------------------------------------------------- */

/* The next line at or after *pp that is neither blank nor a comment: its first non-blank
   byte in *line and its end in *eol; 0 at the end of the data. */
static int cloth__next_content_line(const unsigned char **pp, const unsigned char *end, const unsigned char **line,
                                    const unsigned char **eol)
{
    const unsigned char *p = *pp;
    while (p < end) {
        const unsigned char *e = cloth__line_end(p, end), *q = cloth__skip_blank(p, e);
        p = e < end ? e + 1 : end;
        if (q < e && *q != '#') {
            *line = q;
            *eol = e;
            *pp = p;
            return 1;
        }
    }
    *pp = end;
    return 0;
}

/* Whether [p, e) is an OFF keyword: OFF with any of the prefixes ST, C, N, 4 and n. *plain is
   cleared by the 4 (four-dimensional) and n (n-dimensional) prefixes, which cloth.h does not read. */
static int cloth__off_keyword(const unsigned char *p, const unsigned char *e, int *plain)
{
    *plain = 1;
    if (e - p < 3 || memcmp(e - 3, "OFF", 3) != 0) return 0;
    for (; p < e - 3; ++p) {
        if (*p == '4' || *p == 'n') *plain = 0;
        else if (*p != 'S' && *p != 'T' && *p != 'C' && *p != 'N') return 0;
    }
    return 1;
}

static cloth_result cloth__read_off(const cloth__io *io, cloth_mesh *mesh)
{
    const unsigned char *end = io->end, *p = cloth__skip_bom(io->begin, end), *line = NULL, *eol = NULL, *k, *body;
    int64_t vertex_count = 0, face_count = 0, triangles = 0, i, j;
    int plain = 1;
    cloth_result r;
    if (!cloth__next_content_line(&p, end, &line, &eol))
        return cloth__io_fail(io, CLOTH_ERROR_EMPTY_MESH, end, 1, "the OFF file is empty");
    k = line;
    line = cloth__obj_keyword_end(line, eol);
    if (!cloth__off_keyword(k, line, &plain))
        return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "not an OFF file: the first word is not OFF");
    if (!plain) return cloth__io_fail(io, CLOTH_ERROR_UNSUPPORTED, k, 1, "OFF files of other than three dimensions");
    line = cloth__skip_blank(line, eol);
    if (line < eol && *line != '#') {
        if (cloth__starts_with(line, eol, "BINARY")) return cloth__io_fail(io, CLOTH_ERROR_UNSUPPORTED, line, 1, "binary OFF");
    } else if (!cloth__next_content_line(&p, end, &line, &eol)) {
        return cloth__io_fail(io, CLOTH_ERROR_TRUNCATED, end, 1, "the OFF file ends before its counts");
    }
    if ((r = cloth__text_int(io, &line, eol, &vertex_count, "vertex count")) != CLOTH_SUCCESS) return r;
    if ((r = cloth__text_int(io, &line, eol, &face_count, "face count")) != CLOTH_SUCCESS) return r;
    if (vertex_count < 0 || face_count < 0)
        return cloth__io_fail(io, CLOTH_ERROR_PARSE, line, 1, "negative counts %lld %lld", (long long)vertex_count,
                              (long long)face_count);
    body = p;
    /* First pass: every vertex line is there; count the triangles of the faces. */
    for (i = 0; i < vertex_count; ++i)
        if (!cloth__next_content_line(&p, end, &line, &eol))
            return cloth__io_fail(io, CLOTH_ERROR_TRUNCATED, end, 1, "the header announces %lld vertices, the file has %lld",
                                  (long long)vertex_count, (long long)i);
    for (i = 0; i < face_count; ++i) {
        int64_t corners = 0;
        if (!cloth__next_content_line(&p, end, &line, &eol))
            return cloth__io_fail(io, CLOTH_ERROR_TRUNCATED, end, 1, "the header announces %lld faces, the file has %lld",
                                  (long long)face_count, (long long)i);
        k = line;
        if ((r = cloth__text_int(io, &line, eol, &corners, "face vertex count")) != CLOTH_SUCCESS) return r;
        if (corners < 3)
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "face %lld has %lld vertices (at least 3 needed)", (long long)i,
                                  (long long)corners);
        if (corners > (eol - line) / 2) /* each index takes at least two bytes of the line */
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1,
                                  "face %lld announces %lld vertices; its line is too short for them", (long long)i,
                                  (long long)corners);
        triangles += corners - 2;
    }
    if ((r = cloth__io_mesh_alloc(io, mesh, vertex_count, triangles, 0, 1)) != CLOTH_SUCCESS) return r;
    /* Second pass: read. */
    p = body;
    for (i = 0; i < vertex_count; ++i) {
        cloth_real *x = mesh->x + 3 * i;
        cloth__next_content_line(&p, end, &line, &eol);
        if ((r = cloth__text_real(io, &line, eol, x, "vertex x")) != CLOTH_SUCCESS) return r;
        if ((r = cloth__text_real(io, &line, eol, x + 1, "vertex y")) != CLOTH_SUCCESS) return r;
        if ((r = cloth__text_real(io, &line, eol, x + 2, "vertex z")) != CLOTH_SUCCESS) return r;
    }
    {
        int32_t *tri = mesh->tri;
        for (i = 0; i < face_count; ++i) {
            int64_t corners = 0;
            int32_t first = 0, previous = 0;
            cloth__next_content_line(&p, end, &line, &eol);
            cloth__text_int(io, &line, eol, &corners, "face vertex count");
            for (j = 0; j < corners; ++j) {
                int64_t v = 0;
                const unsigned char *at = cloth__skip_blank(line, eol);
                if ((r = cloth__text_int(io, &line, eol, &v, "face index")) != CLOTH_SUCCESS) return r;
                if (v < 0 || v >= vertex_count)
                    return cloth__io_fail(io, CLOTH_ERROR_INDEX_OUT_OF_RANGE, at, 1, "face %lld names vertex %lld of %lld",
                                          (long long)i, (long long)v, (long long)vertex_count);
                if (j == 0) first = (int32_t)v;
                if (j >= 2) {
                    tri[0] = first;
                    tri[1] = previous;
                    tri[2] = (int32_t)v;
                    tri += 3;
                }
                previous = (int32_t)v;
            }
        }
    }
    return CLOTH_SUCCESS;
}

/* ---- format detection and the public readers -------------------------------------------- */

CLOTH_API cloth_file_format cloth_detect_format(const void *data, size_t size)
{
    const unsigned char *begin = (const unsigned char *)data, *end = begin + (data ? size : 0), *p, *line, *eol;
    int plain = 1;
    if (!data || size == 0) return CLOTH_FORMAT_AUTO;
    p = cloth__skip_bom(begin, end);
    if (end - p >= 3 && memcmp(p, "ply", 3) == 0 && (end - p == 3 || p[3] == '\n' || p[3] == '\r')) {
        /* the encoding from the format line of the header */
        for (p = cloth__line_end(p, end); p < end; p = cloth__line_end(p + 1, end)) {
            const unsigned char *w[3], *we[3];
            int n;
            eol = cloth__line_end(p + 1, end);
            n = cloth__split_line(p + 1, eol, w, we, 3);
            if (n >= 1 && cloth__bytes_are(w[0], we[0], "end_header")) break;
            if (n >= 2 && cloth__bytes_are(w[0], we[0], "format")) {
                if (cloth__bytes_are(w[1], we[1], "binary_little_endian")) return CLOTH_FORMAT_PLY_BINARY_LE;
                if (cloth__bytes_are(w[1], we[1], "binary_big_endian")) return CLOTH_FORMAT_PLY_BINARY_BE;
                break;
            }
        }
        return CLOTH_FORMAT_PLY_ASCII;
    }
    if (cloth__starts_with(cloth__skip_blank(p, end), end, "# vtk DataFile")) {
        /* ASCII or BINARY on the third line */
        eol = cloth__line_end(p, end);
        if (eol < end) eol = cloth__line_end(eol + 1, end);
        if (eol < end) {
            const unsigned char *w[2], *we[2];
            line = eol + 1;
            eol = cloth__line_end(line, end);
            if (cloth__split_line(line, eol, w, we, 2) == 1 && cloth__token_is(w[0], we[0], "BINARY"))
                return CLOTH_FORMAT_VTK_BINARY;
        }
        return CLOTH_FORMAT_VTK_ASCII;
    }
    if (cloth__next_content_line(&p, end, &line, &eol)) {
        const unsigned char *k = cloth__obj_keyword_end(line, eol);
        if (cloth__off_keyword(line, k, &plain)) return CLOTH_FORMAT_OFF;
        if (cloth__obj_keyword(line, k) != CLOTH__OBJ_UNKNOWN) return CLOTH_FORMAT_OBJ;
    }
    return CLOTH_FORMAT_AUTO;
}

/* The format of a path's extension, CLOTH_FORMAT_AUTO when it has none that cloth.h knows;
   `writing` picks binary PLY and VTK. */
static cloth_file_format cloth__format_of_path(const char *path, int writing)
{
    const char *dot = strrchr(path, '.');
    const unsigned char *e;
    if (!dot) return CLOTH_FORMAT_AUTO;
    e = (const unsigned char *)dot + strlen(dot);
    if (cloth__token_is((const unsigned char *)dot, e, ".obj")) return CLOTH_FORMAT_OBJ;
    if (cloth__token_is((const unsigned char *)dot, e, ".ply"))
        return writing ? CLOTH_FORMAT_PLY_BINARY_LE : CLOTH_FORMAT_PLY_ASCII;
    if (cloth__token_is((const unsigned char *)dot, e, ".vtk")) return writing ? CLOTH_FORMAT_VTK_BINARY : CLOTH_FORMAT_VTK_ASCII;
    if (cloth__token_is((const unsigned char *)dot, e, ".off")) return CLOTH_FORMAT_OFF;
    return CLOTH_FORMAT_AUTO;
}

static cloth_result cloth__read_format(cloth_mesh *mesh, const void *data, size_t size, cloth_file_format format,
                                       cloth_io_error *error, const cloth_allocator *allocator, const char *path)
{
    cloth_io_error local;
    cloth__io io;
    cloth_result r;
    CLOTH_ASSERT(mesh != NULL);
    CLOTH_ASSERT(data != NULL || size == 0);
    memset(mesh, 0, sizeof *mesh);
    io.begin = (const unsigned char *)data;
    io.end = io.begin + (data ? size : 0);
    io.error = error ? error : &local;
    io.allocator = cloth__allocator_or_default(allocator);
    memset(io.error, 0, sizeof *io.error);
    if (!data) io.begin = io.end = (const unsigned char *)"";
    if (cloth__skip_space(io.begin, io.end) == io.end)
        return cloth__io_fail(&io, CLOTH_ERROR_EMPTY_MESH, io.end, 1, "the input is empty");
    if (format == CLOTH_FORMAT_AUTO) format = cloth_detect_format(io.begin, size);
    if (format == CLOTH_FORMAT_AUTO && path) format = cloth__format_of_path(path, 0);
    if (format == CLOTH_FORMAT_AUTO)
        return cloth__io_fail(&io, CLOTH_ERROR_PARSE, io.begin, 1, "the content is not OBJ, PLY, VTK legacy or OFF");
    switch (format) {
    case CLOTH_FORMAT_OBJ: r = cloth__read_obj(&io, mesh); break;
    case CLOTH_FORMAT_PLY_ASCII:
    case CLOTH_FORMAT_PLY_BINARY_LE:
    case CLOTH_FORMAT_PLY_BINARY_BE: r = cloth__read_ply(&io, mesh); break;
    case CLOTH_FORMAT_VTK_ASCII:
    case CLOTH_FORMAT_VTK_BINARY: r = cloth__read_vtk(&io, mesh); break;
    case CLOTH_FORMAT_OFF: r = cloth__read_off(&io, mesh); break;
    default: r = cloth__io_fail(&io, CLOTH_ERROR_INVALID_ARGUMENT, NULL, 0, "unknown file format %d", (int)format); break;
    }
    if (r != CLOTH_SUCCESS) {
        if (mesh->x || mesh->tri || mesh->uv) cloth_mesh_free(mesh);
        memset(mesh, 0, sizeof *mesh);
    }
    return r;
}

CLOTH_API cloth_result cloth_mesh_read_memory(cloth_mesh *mesh, const void *data, size_t size, cloth_file_format format,
                                              cloth_io_error *error, const cloth_allocator *allocator)
{
    return cloth__read_format(mesh, data, size, format, error, allocator, NULL);
}

/* ---- writing ------------------------------------------------------------------------- */

/* Where a writer's bytes go: a buffer that grows (memory) or one that is flushed to a file. */
typedef struct cloth__sink {
    unsigned char *data;
    size_t size, capacity;
    cloth_allocator allocator; /* memory: what the buffer grows with */
    void *file;                /* a FILE * when writing a file, else NULL */
    cloth_result result;
} cloth__sink;

/* Room for n more bytes (a short piece: a number, a record, a header line), or NULL after
   a failure (recorded in s->result). */
static unsigned char *cloth__sink_room(cloth__sink *s, size_t n)
{
    if (s->result != CLOTH_SUCCESS) return NULL;
    if (s->capacity - s->size >= n) return s->data + s->size;
#ifndef CLOTH_NO_STDIO
    if (s->file) {
        if (n > s->capacity || fwrite(s->data, 1, s->size, (FILE *)s->file) != s->size) {
            s->result = CLOTH_ERROR_FILE_WRITE;
            return NULL;
        }
        s->size = 0;
        return s->data;
    }
#endif
    {
        size_t capacity = s->capacity < 4096 ? 4096 : s->capacity;
        unsigned char *grown;
        while (capacity - s->size < n) {
            if (capacity > SIZE_MAX / 2) {
                s->result = CLOTH_ERROR_SIZE_OVERFLOW;
                return NULL;
            }
            capacity *= 2;
        }
        grown = (unsigned char *)s->allocator.alloc(capacity, s->allocator.user);
        if (!grown) {
            s->result = CLOTH_ERROR_OUT_OF_MEMORY;
            return NULL;
        }
        if (s->size) memcpy(grown, s->data, s->size);
        cloth__free(&s->allocator, s->data);
        s->data = grown;
        s->capacity = capacity;
        return grown + s->size;
    }
}

static void cloth__sink_bytes(cloth__sink *s, const void *bytes, size_t n)
{
    unsigned char *room = cloth__sink_room(s, n);
    if (!room) return;
    memcpy(room, bytes, n);
    s->size += n;
}

static void cloth__sink_text(cloth__sink *s, const char *text) { cloth__sink_bytes(s, text, strlen(text)); }

/* A real with enough digits to round-trip, followed by `after`. The decimal separator of
   the C locale is forced back to '.', so a locale with a decimal comma does not leak in. */
static void cloth__sink_real(cloth__sink *s, cloth_real value, char after)
{
    char text[40];
    int n = snprintf(text, sizeof text, sizeof(cloth_real) == sizeof(float) ? "%.9g" : "%.17g", (double)value), i;
    unsigned char *room;
    if (n <= 0 || n >= (int)sizeof text - 1) {
        s->result = CLOTH_ERROR_FILE_WRITE;
        return;
    }
    for (i = 0; i < n; ++i)
        if (!cloth__is_digit(text[i]) && text[i] != '-' && text[i] != '+' && text[i] != 'e') text[i] = '.';
    text[n++] = after;
    if ((room = cloth__sink_room(s, (size_t)n)) == NULL) return;
    memcpy(room, text, (size_t)n);
    s->size += (size_t)n;
}

/* A non-negative integer followed by `after`. */
static void cloth__sink_int(cloth__sink *s, int64_t value, char after)
{
    char text[24];
    int n = 0, i;
    unsigned char *room;
    uint64_t v = value < 0 ? 0 : (uint64_t)value;
    do {
        text[n++] = (char)('0' + v % 10);
        v /= 10;
    } while (v);
    if ((room = cloth__sink_room(s, (size_t)n + 1)) == NULL) return;
    for (i = 0; i < n; ++i) room[i] = (unsigned char)text[n - 1 - i];
    room[n] = (unsigned char)after;
    s->size += (size_t)n + 1;
}

static void cloth__store_u32(unsigned char *p, uint32_t v, int big_endian)
{
    int i;
    for (i = 0; i < 4; ++i) p[big_endian ? 3 - i : i] = (unsigned char)(v >> (8 * i));
}

static void cloth__store_f64(unsigned char *p, double value, int big_endian)
{
    uint64_t v;
    int i;
    memcpy(&v, &value, sizeof v);
    for (i = 0; i < 8; ++i) p[big_endian ? 7 - i : i] = (unsigned char)(v >> (8 * i));
}

/* A mesh that cloth.h can read back: vertices and triangles, finite numbers, indices in range. */
static cloth_result cloth__write_check(const cloth_mesh *mesh)
{
    int64_t i;
    if (mesh->vertex_count <= 0 || mesh->triangle_count <= 0) return CLOTH_ERROR_EMPTY_MESH;
    if (!mesh->x || !mesh->tri) return CLOTH_ERROR_INVALID_ARGUMENT;
    for (i = 0; i < 3 * (int64_t)mesh->vertex_count; ++i)
        if (!cloth__is_finite(mesh->x[i])) return CLOTH_ERROR_NOT_FINITE;
    if (mesh->uv)
        for (i = 0; i < 2 * (int64_t)mesh->vertex_count; ++i)
            if (!cloth__is_finite(mesh->uv[i])) return CLOTH_ERROR_NOT_FINITE;
    for (i = 0; i < 3 * (int64_t)mesh->triangle_count; ++i)
        if (mesh->tri[i] < 0 || mesh->tri[i] >= mesh->vertex_count) return CLOTH_ERROR_INDEX_OUT_OF_RANGE;
    return CLOTH_SUCCESS;
}

static void cloth__write_obj(cloth__sink *s, const cloth_mesh *m)
{
    int64_t i;
    cloth__sink_text(s, "# written by cloth.h " CLOTH_VERSION_STRING "\n");
    for (i = 0; i < m->vertex_count && s->result == CLOTH_SUCCESS; ++i) {
        cloth__sink_text(s, "v ");
        cloth__sink_real(s, m->x[3 * i], ' ');
        cloth__sink_real(s, m->x[3 * i + 1], ' ');
        cloth__sink_real(s, m->x[3 * i + 2], '\n');
    }
    for (i = 0; m->uv && i < m->vertex_count && s->result == CLOTH_SUCCESS; ++i) {
        cloth__sink_text(s, "vt ");
        cloth__sink_real(s, m->uv[2 * i], ' ');
        cloth__sink_real(s, m->uv[2 * i + 1], '\n');
    }
    for (i = 0; i < m->triangle_count && s->result == CLOTH_SUCCESS; ++i) {
        int k;
        cloth__sink_text(s, "f ");
        for (k = 0; k < 3; ++k) {
            int64_t v = (int64_t)m->tri[3 * i + k] + 1;
            if (m->uv) cloth__sink_int(s, v, '/');
            cloth__sink_int(s, v, k == 2 ? '\n' : ' ');
        }
    }
}

static void cloth__write_ply(cloth__sink *s, const cloth_mesh *m, cloth_file_format format)
{
    int binary = format != CLOTH_FORMAT_PLY_ASCII, big_endian = format == CLOTH_FORMAT_PLY_BINARY_BE;
    int64_t i;
    cloth__sink_text(s, "ply\nformat ");
    cloth__sink_text(s, !binary ? "ascii" : big_endian ? "binary_big_endian" : "binary_little_endian");
    cloth__sink_text(s, " 1.0\ncomment written by cloth.h " CLOTH_VERSION_STRING "\nelement vertex ");
    cloth__sink_int(s, m->vertex_count, '\n');
    cloth__sink_text(s, "property double x\nproperty double y\nproperty double z\n");
    if (m->uv) cloth__sink_text(s, "property double u\nproperty double v\n");
    cloth__sink_text(s, "element face ");
    cloth__sink_int(s, m->triangle_count, '\n');
    cloth__sink_text(s, "property list uchar int vertex_indices\nend_header\n");
    for (i = 0; i < m->vertex_count && s->result == CLOTH_SUCCESS; ++i) {
        if (binary) {
            unsigned char record[40];
            size_t n = m->uv ? 40 : 24;
            cloth__store_f64(record, (double)m->x[3 * i], big_endian);
            cloth__store_f64(record + 8, (double)m->x[3 * i + 1], big_endian);
            cloth__store_f64(record + 16, (double)m->x[3 * i + 2], big_endian);
            if (m->uv) {
                cloth__store_f64(record + 24, (double)m->uv[2 * i], big_endian);
                cloth__store_f64(record + 32, (double)m->uv[2 * i + 1], big_endian);
            }
            cloth__sink_bytes(s, record, n);
        } else {
            cloth__sink_real(s, m->x[3 * i], ' ');
            cloth__sink_real(s, m->x[3 * i + 1], ' ');
            cloth__sink_real(s, m->x[3 * i + 2], m->uv ? ' ' : '\n');
            if (m->uv) {
                cloth__sink_real(s, m->uv[2 * i], ' ');
                cloth__sink_real(s, m->uv[2 * i + 1], '\n');
            }
        }
    }
    for (i = 0; i < m->triangle_count && s->result == CLOTH_SUCCESS; ++i) {
        const int32_t *t = m->tri + 3 * i;
        if (binary) {
            unsigned char record[13];
            record[0] = 3;
            cloth__store_u32(record + 1, (uint32_t)t[0], big_endian);
            cloth__store_u32(record + 5, (uint32_t)t[1], big_endian);
            cloth__store_u32(record + 9, (uint32_t)t[2], big_endian);
            cloth__sink_bytes(s, record, sizeof record);
        } else {
            cloth__sink_text(s, "3 ");
            cloth__sink_int(s, t[0], ' ');
            cloth__sink_int(s, t[1], ' ');
            cloth__sink_int(s, t[2], '\n');
        }
    }
}

static void cloth__write_vtk(cloth__sink *s, const cloth_mesh *m, int binary)
{
    int64_t i;
    cloth__sink_text(s, "# vtk DataFile Version 4.2\nwritten by cloth.h " CLOTH_VERSION_STRING "\n");
    cloth__sink_text(s, binary ? "BINARY\n" : "ASCII\n");
    cloth__sink_text(s, "DATASET UNSTRUCTURED_GRID\nPOINTS ");
    cloth__sink_int(s, m->vertex_count, ' ');
    cloth__sink_text(s, "double\n");
    for (i = 0; i < m->vertex_count && s->result == CLOTH_SUCCESS; ++i) {
        if (binary) {
            unsigned char record[24];
            cloth__store_f64(record, (double)m->x[3 * i], 1);
            cloth__store_f64(record + 8, (double)m->x[3 * i + 1], 1);
            cloth__store_f64(record + 16, (double)m->x[3 * i + 2], 1);
            cloth__sink_bytes(s, record, sizeof record);
        } else {
            cloth__sink_real(s, m->x[3 * i], ' ');
            cloth__sink_real(s, m->x[3 * i + 1], ' ');
            cloth__sink_real(s, m->x[3 * i + 2], '\n');
        }
    }
    cloth__sink_text(s, binary ? "\nCELLS " : "CELLS ");
    cloth__sink_int(s, m->triangle_count, ' ');
    cloth__sink_int(s, 4 * (int64_t)m->triangle_count, '\n');
    for (i = 0; i < m->triangle_count && s->result == CLOTH_SUCCESS; ++i) {
        const int32_t *t = m->tri + 3 * i;
        if (binary) {
            unsigned char record[16];
            cloth__store_u32(record, 3, 1);
            cloth__store_u32(record + 4, (uint32_t)t[0], 1);
            cloth__store_u32(record + 8, (uint32_t)t[1], 1);
            cloth__store_u32(record + 12, (uint32_t)t[2], 1);
            cloth__sink_bytes(s, record, sizeof record);
        } else {
            cloth__sink_text(s, "3 ");
            cloth__sink_int(s, t[0], ' ');
            cloth__sink_int(s, t[1], ' ');
            cloth__sink_int(s, t[2], '\n');
        }
    }
    cloth__sink_text(s, binary ? "\nCELL_TYPES " : "CELL_TYPES ");
    cloth__sink_int(s, m->triangle_count, '\n');
    for (i = 0; i < m->triangle_count && s->result == CLOTH_SUCCESS; ++i) {
        if (binary) {
            unsigned char record[4];
            cloth__store_u32(record, 5, 1);
            cloth__sink_bytes(s, record, sizeof record);
        } else {
            cloth__sink_text(s, "5\n");
        }
    }
    if (binary) cloth__sink_text(s, "\n");
}

static void cloth__write_off(cloth__sink *s, const cloth_mesh *m)
{
    int64_t i;
    cloth__sink_text(s, "OFF\n");
    cloth__sink_int(s, m->vertex_count, ' ');
    cloth__sink_int(s, m->triangle_count, ' ');
    cloth__sink_text(s, "0\n");
    for (i = 0; i < m->vertex_count && s->result == CLOTH_SUCCESS; ++i) {
        cloth__sink_real(s, m->x[3 * i], ' ');
        cloth__sink_real(s, m->x[3 * i + 1], ' ');
        cloth__sink_real(s, m->x[3 * i + 2], '\n');
    }
    for (i = 0; i < m->triangle_count && s->result == CLOTH_SUCCESS; ++i) {
        cloth__sink_text(s, "3 ");
        cloth__sink_int(s, m->tri[3 * i], ' ');
        cloth__sink_int(s, m->tri[3 * i + 1], ' ');
        cloth__sink_int(s, m->tri[3 * i + 2], '\n');
    }
}

static cloth_result cloth__write_sink(cloth__sink *s, const cloth_mesh *mesh, cloth_file_format format)
{
    cloth_result r = cloth__write_check(mesh);
    if (r != CLOTH_SUCCESS) return r;
    switch (format) {
    case CLOTH_FORMAT_OBJ: cloth__write_obj(s, mesh); break;
    case CLOTH_FORMAT_PLY_ASCII:
    case CLOTH_FORMAT_PLY_BINARY_LE:
    case CLOTH_FORMAT_PLY_BINARY_BE: cloth__write_ply(s, mesh, format); break;
    case CLOTH_FORMAT_VTK_ASCII:
    case CLOTH_FORMAT_VTK_BINARY: cloth__write_vtk(s, mesh, format == CLOTH_FORMAT_VTK_BINARY); break;
    case CLOTH_FORMAT_OFF: cloth__write_off(s, mesh); break;
    default: return CLOTH_ERROR_INVALID_ARGUMENT;
    }
    return s->result;
}

CLOTH_API cloth_result cloth_mesh_write_memory(const cloth_mesh *mesh, cloth_file_format format, void **data, size_t *size,
                                               const cloth_allocator *allocator)
{
    cloth__sink s;
    cloth_result r;
    CLOTH_ASSERT(mesh != NULL && data != NULL && size != NULL);
    *data = NULL;
    *size = 0;
    memset(&s, 0, sizeof s);
    s.allocator = cloth__allocator_or_default(allocator);
    r = cloth__write_sink(&s, mesh, format);
    if (r != CLOTH_SUCCESS) {
        cloth__free(&s.allocator, s.data);
        return r;
    }
    *data = s.data;
    *size = s.size;
    return CLOTH_SUCCESS;
}

#ifndef CLOTH_NO_STDIO
/* The whole file at path in a buffer from the allocator. */
static cloth_result cloth__read_whole_file(const char *path, const cloth_allocator *allocator, unsigned char **data, size_t *size,
                                           cloth_io_error *error)
{
    FILE *f = fopen(path, "rb");
    unsigned char *buffer = NULL;
    size_t used = 0, capacity = 0;
    long length;
    int first;
    *data = NULL;
    *size = 0;
    if (!f) {
        snprintf(error->message, sizeof error->message, "cannot open '%.120s'", path);
        return CLOTH_ERROR_FILE_OPEN;
    }
    /* The size when the file can tell it (after a first byte could be read: a directory may
       claim any size), then grow for files that grow or cannot seek. */
    if (fseek(f, 0, SEEK_END) == 0 && (length = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0) capacity = (size_t)length + 1;
    else rewind(f);
    first = fgetc(f);
    if (first == EOF) {
        int failed = ferror(f);
        fclose(f);
        if (failed) {
            snprintf(error->message, sizeof error->message, "cannot read '%.120s'", path);
            return CLOTH_ERROR_FILE_READ;
        }
        *data = (unsigned char *)cloth__alloc_array(allocator, 0, 1); /* an empty file: an empty buffer */
        if (*data) return CLOTH_SUCCESS;
        snprintf(error->message, sizeof error->message, "out of memory");
        return CLOTH_ERROR_OUT_OF_MEMORY;
    }
    if (capacity < 4096) capacity = 4096;
    for (;;) {
        size_t got;
        if (!buffer || used == capacity) {
            unsigned char *grown;
            size_t next = buffer ? capacity * 2 : capacity;
            if (buffer && capacity > SIZE_MAX / 2) {
                cloth__free(allocator, buffer);
                fclose(f);
                snprintf(error->message, sizeof error->message, "'%.120s' is too large", path);
                return CLOTH_ERROR_SIZE_OVERFLOW;
            }
            grown = (unsigned char *)cloth__alloc_array(allocator, next, 1);
            if (!grown) {
                cloth__free(allocator, buffer);
                fclose(f);
                snprintf(error->message, sizeof error->message, "cannot allocate %lu bytes for '%.100s'", (unsigned long)next,
                         path);
                return CLOTH_ERROR_OUT_OF_MEMORY;
            }
            if (used) memcpy(grown, buffer, used);
            else grown[used++] = (unsigned char)first;
            cloth__free(allocator, buffer);
            buffer = grown;
            capacity = next;
        }
        got = fread(buffer + used, 1, capacity - used, f);
        used += got;
        if (got == 0 || used < capacity) {
            if (ferror(f)) {
                cloth__free(allocator, buffer);
                fclose(f);
                snprintf(error->message, sizeof error->message, "cannot read '%.120s'", path);
                return CLOTH_ERROR_FILE_READ;
            }
            if (feof(f)) break;
        }
    }
    fclose(f);
    *data = buffer;
    *size = used;
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_mesh_read_file(cloth_mesh *mesh, const char *path, cloth_file_format format, cloth_io_error *error,
                                            const cloth_allocator *allocator)
{
    cloth_io_error local;
    cloth_allocator a = cloth__allocator_or_default(allocator);
    unsigned char *data = NULL;
    size_t size = 0;
    cloth_result r;
    CLOTH_ASSERT(mesh != NULL && path != NULL);
    if (!error) error = &local;
    memset(mesh, 0, sizeof *mesh);
    memset(error, 0, sizeof *error);
    r = cloth__read_whole_file(path, &a, &data, &size, error);
    if (r != CLOTH_SUCCESS) return r;
    r = cloth__read_format(mesh, data, size, format, error, &a, path);
    cloth__free(&a, data);
    return r;
}

CLOTH_API cloth_result cloth_mesh_write_file(const cloth_mesh *mesh, const char *path, cloth_file_format format)
{
    unsigned char buffer[16384];
    cloth__sink s;
    cloth_result r;
    FILE *f;
    CLOTH_ASSERT(mesh != NULL && path != NULL);
    if (format == CLOTH_FORMAT_AUTO) format = cloth__format_of_path(path, 1);
    if (format == CLOTH_FORMAT_AUTO) return CLOTH_ERROR_INVALID_ARGUMENT;
    if ((r = cloth__write_check(mesh)) != CLOTH_SUCCESS) return r;
    f = fopen(path, "wb");
    if (!f) return CLOTH_ERROR_FILE_OPEN;
    memset(&s, 0, sizeof s);
    s.data = buffer;
    s.capacity = sizeof buffer;
    s.file = f;
    r = cloth__write_sink(&s, mesh, format);
    if (r == CLOTH_SUCCESS && s.size && fwrite(s.data, 1, s.size, f) != s.size) r = CLOTH_ERROR_FILE_WRITE;
    if (fclose(f) != 0 && r == CLOTH_SUCCESS) r = CLOTH_ERROR_FILE_WRITE;
    return r;
}
#endif /* CLOTH_NO_STDIO */
