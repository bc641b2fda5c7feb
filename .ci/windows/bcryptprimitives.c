/* For running raycast.exe under Debian's Wine 8 in CI only: Rust's standard library (1.78 and
 * later) asks bcryptprimitives.dll for ProcessPrng, which Windows 10 and 11 have and Wine 8
 * does not. This stands in for it over RtlGenRandom (advapi32's SystemFunction036). It is
 * never shipped: a real Windows has its own. */
#include <windows.h>

BOOLEAN WINAPI SystemFunction036(PVOID buffer, ULONG length);

__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T length)
{
    while (length > 0) {
        ULONG chunk = length > 0x10000000 ? 0x10000000 : (ULONG)length;
        if (!SystemFunction036(data, chunk)) {
            return FALSE;
        }
        data += chunk;
        length -= chunk;
    }
    return TRUE;
}
