# cython: boundscheck=False, wraparound=False
"""The fast log decoders' C loops. DataFlash (:mod:`fusion_altitude.logs._dataflash_fast`): the message index
(``_dataflash_scan.h``), the FMT messages checked and read, the bodies of the asked-for types grouped by type.
ULog (:mod:`fusion_altitude.logs._ulog_fast`): the message walk (``_ulog_scan.h``), the info/parameter and format
checks, the samples of each subscription gathered from the data section."""

import numpy as np

from libc.stdint cimport int16_t, int32_t, uint8_t, uint32_t, uint64_t
from libc.math cimport NAN
from libc.string cimport memcpy, memset
from cpython.mem cimport PyMem_Free, PyMem_Malloc

cdef extern from "_scan_common.h":
    void ScanCountTypes(const uint8_t *types, size_t count, uint64_t *counts) nogil

cdef extern from "_dataflash_scan.h":
    ctypedef enum DataFlashScanStatus:
        DataFlashScanOk
        DataFlashScanBadFmtLength
        DataFlashScanUnknownType
        DataFlashScanFull
    ctypedef struct DataFlashScanResult:
        size_t count
        size_t badHeaders
        size_t stopOffset
        uint8_t lengths[256]
    DataFlashScanStatus DataFlashScan(const uint8_t *data, size_t size, uint64_t *offsets, uint8_t *types,
                                      size_t capacity, DataFlashScanResult *result) nogil
    size_t DataFlashGather(const uint8_t *data, size_t size, const uint64_t *offsets, size_t count, size_t length,
                           uint8_t *out) nogil
    size_t DataFlashCharSize(uint8_t c) nogil
    void DataFlashColumnIndexes(const uint8_t *columns, size_t columnsLength, const char *const *names,
                                const size_t *nameLengths, size_t nameCount, int16_t *index) nogil
    size_t DataFlashFieldOffset(const uint8_t *chars, size_t index) nogil
    void DataFlashSplit(const uint64_t *offsets, const uint8_t *types, size_t count, uint64_t *const *rows) nogil
    ctypedef enum DataFlashColumnStatus:
        DataFlashColumnOk
        DataFlashColumnNotNumeric
        DataFlashColumnOutside
    DataFlashColumnStatus DataFlashColumn(const uint8_t *data, size_t size, const uint64_t *offsets, size_t count,
                                          size_t fieldOffset, uint8_t formatChar, double *out) nogil
    enum: DATAFLASH_NAME_SLOTS
    uint32_t DataFlashNameKey(const uint8_t *name) nogil
    uint8_t DataFlashCharStruct(uint8_t c) nogil
    int DataFlashNameSeen(uint64_t *slots, uint32_t key) nogil

#: Status names of :func:`dataflash_index`.
STATUS = {0: "ok", 1: "bad FMT length", 2: "unknown type", 3: "full"}


def dataflash_index(const uint8_t[::1] data):
    """Where each message of a DataFlash log starts and its type, in one pass (as pymavlink's indexer).

    Parameters
    ----------
    data : bytes-like
        The whole file.

    Returns
    -------
    offsets : ndarray of uint64
        Start of each message (byte offset of its 0xA3 0x95 header), in file order.
    types : ndarray of uint8
        Message type of each.
    bad_headers : int
        Bytes stepped over that start no header (not counted in the last 528 bytes of a file of 528 or more).
    status : str
        "ok", or where pymavlink's indexer would stop the program: "bad FMT length", "unknown type".
    stop_offset : int
        Byte where an error status was met (else the size).
    lengths : ndarray of uint8, shape (256,)
        Message length (bytes, header included) of each type at the end of the scan; 0 for undefined types.
    """
    cdef size_t size = data.shape[0]
    cdef size_t capacity = size // 3 + 1
    offsets = np.empty(capacity, dtype=np.uint64)
    types = np.empty(capacity, dtype=np.uint8)
    cdef uint64_t[::1] offsets_view = offsets
    cdef uint8_t[::1] types_view = types
    cdef DataFlashScanResult result
    cdef DataFlashScanStatus status
    cdef const uint8_t *start = &data[0] if size > 0 else NULL
    if size == 0:
        return offsets[:0], types[:0], 0, "ok", 0, np.zeros(256, dtype=np.uint8)
    with nogil:
        status = DataFlashScan(start, size, &offsets_view[0], &types_view[0], capacity, &result)
    lengths = np.empty(256, dtype=np.uint8)
    cdef uint8_t[::1] length_view = lengths
    memcpy(&length_view[0], &result.lengths[0], 256)
    return (offsets[:result.count], types[:result.count], int(result.badHeaders), STATUS[<int> status],
            int(result.stopOffset), lengths)


def dataflash_gather(const uint8_t[::1] data, const uint64_t[::1] offsets, size_t length):
    """The bodies of the messages at ``offsets`` (each ``length`` bytes with its 3-byte header), one row each.

    Returns
    -------
    bodies : ndarray of uint8, shape (len(offsets), length - 3)
        Bodies running past the end of ``data`` are zero-padded.
    complete : int
        How many bodies lie wholly inside ``data``.
    """
    cdef size_t count = offsets.shape[0]
    if length < 3:
        raise ValueError(f"length must be at least 3 bytes, got {length}")
    out = np.empty((count, length - 3), dtype=np.uint8)
    if count == 0 or length == 3:
        return out, count
    cdef uint8_t[:, ::1] out_view = out
    cdef size_t complete
    with nogil:
        complete = DataFlashGather(&data[0], data.shape[0], &offsets[0], count, length, &out_view[0, 0])
    return out, int(complete)


cdef extern from "_ulog_scan.h":
    ctypedef struct ULogMessages:
        uint64_t *offsets
        uint8_t *types
        unsigned short *sizes
        size_t capacity
    ctypedef struct ULogDefinitionsResult:
        size_t count
        size_t sectionStart
        int found
        int cut
        int full
    ctypedef struct ULogDataResult:
        size_t count
        size_t segmentEnds[4]
        size_t segments
        size_t skipped
        size_t synced
        int full
    size_t ULogPlainEnd(const uint8_t *data, size_t size, size_t start) nogil
    void ULogWalkDefinitions(const uint8_t *data, size_t size, size_t start, const ULogMessages *out,
                             ULogDefinitionsResult *result) nogil
    void ULogWalkData(const uint8_t *data, size_t size, size_t sectionStart, const uint64_t *appended,
                      size_t appendedCount, const ULogMessages *out, ULogDataResult *result) nogil
    ctypedef struct ULogSubscriptions:
        const unsigned short *slotOf
        const uint64_t *starts
        const uint64_t *itemsizes
    int ULogCheckInfos(const uint8_t *data, size_t size, const uint64_t *offsets, const unsigned short *sizes,
                       size_t count, size_t skip, uint8_t *verdicts) nogil
    int ULogFormatNameLengths(const uint8_t *data, size_t size, const uint64_t *offsets, const unsigned short *sizes,
                              size_t count, size_t *lengths) nogil
    size_t ULogFirstOutside(size_t size, const uint64_t *offsets, const unsigned short *sizes, size_t count) nogil
    void ULogSamples(const uint8_t *data, const uint64_t *offsets, const uint8_t *types, const unsigned short *sizes,
                     size_t count, const ULogSubscriptions *subscriptions, uint64_t *counts, uint8_t **rows) nogil


cdef _ulog_arrays(size_t capacity, ULogMessages *out):
    """Output arrays (offsets uint64, types uint8, sizes uint16) of ``capacity`` entries, pointed to by ``out``."""
    offsets = np.empty(max(capacity, 1), dtype=np.uint64)
    types = np.empty(max(capacity, 1), dtype=np.uint8)
    sizes = np.empty(max(capacity, 1), dtype=np.uint16)
    cdef uint64_t[::1] offsets_view = offsets
    cdef uint8_t[::1] types_view = types
    cdef unsigned short[::1] sizes_view = sizes
    out.offsets = &offsets_view[0]
    out.types = &types_view[0]
    out.sizes = &sizes_view[0]
    out.capacity = capacity
    return offsets, types, sizes


def ulog_plain_end(const uint8_t[::1] data, size_t start=16):
    """Byte after the last whole message when every header is taken as sound (where a cut file is cut)."""
    if <size_t> data.shape[0] <= start:
        return int(start)
    return int(ULogPlainEnd(&data[0], data.shape[0], start))


def ulog_definitions(const uint8_t[::1] data, size_t start=16):
    """pyulog's walk of a ULog's definitions (from byte ``start``): its I, M, F, P, Q and B messages.

    Returns
    -------
    offsets, types, sizes : ndarrays of uint64, uint8, uint16
        Byte offset of each message's 3-byte header, its type and payload size (bytes), in file order.
    section_start : int
        Byte offset of the data section's first message (an A, L or C message).
    found : bool
        Whether a data section starts there (False: the file ends first).
    cut : bool
        Whether a header or payload is cut by the end of the file before the data section.
    """
    cdef size_t size = data.shape[0]
    cdef ULogMessages out
    cdef ULogDefinitionsResult result
    cdef size_t most = (size - start) // 3 + 1 if size > start else 0
    if size <= start:
        offsets, types, sizes = _ulog_arrays(0, &out)
        return offsets[:0], types[:0], sizes[:0], int(start), False, size < start
    for capacity in (min(most, 4096), most):  # definitions are short: room for all only if needed
        offsets, types, sizes = _ulog_arrays(capacity, &out)
        with nogil:
            ULogWalkDefinitions(&data[0], size, start, &out, &result)
        if not result.full:
            break
    if result.full:
        raise RuntimeError("ulog_definitions: output arrays full (cannot happen: capacity covers 3-byte messages)")
    return (offsets[:result.count], types[:result.count], sizes[:result.count], int(result.sectionStart),
            bool(result.found), bool(result.cut))


def ulog_data_walk(const uint8_t[::1] data, size_t section_start, appended):
    """pyulog's walk of a ULog's data section: the messages it reads, segment by segment.

    Parameters
    ----------
    data : bytes-like
        The whole file.
    section_start : int
        Byte offset of the data section (from :func:`ulog_definitions`).
    appended : sequence of int
        The appended-data offsets pyulog uses (bytes, at most 3, each below 2**63): one segment ends before
        each and the next starts there.

    Returns
    -------
    offsets, types, sizes : ndarrays of uint64, uint8, uint16
        Each message of a known data-section type (I M P Q A L C D O S) read, in pyulog's order.
    segment_ends : list of int
        Messages read after each segment.
    skipped : int
        Messages of unknown type stepped over.
    synced : int
        Times reading resumed after a sync sequence.
    """
    cdef size_t size = data.shape[0]
    cdef uint64_t appended_values[3]
    cdef size_t count = len(appended)
    cdef size_t k
    cdef ULogMessages out
    cdef ULogDataResult result
    if count > 3:
        raise ValueError(f"appended: at most 3 offsets, got {count}")
    for k in range(count):
        if not 0 <= appended[k] < 2 ** 63:
            raise ValueError(f"appended[{k}]: {appended[k]} is not an offset below 2**63")
        appended_values[k] = appended[k]
    capacity = (size - section_start) // 3 + 1 if size > section_start else 1
    while True:  # segments may overlap (appended offsets, sync): grow once, to room for every segment
        offsets, types, sizes = _ulog_arrays(capacity, &out)
        if size == 0:
            return offsets[:0], types[:0], sizes[:0], [0] * (count + 1), 0, 0
        with nogil:
            ULogWalkData(&data[0], size, section_start, appended_values, count, &out, &result)
        if not result.full:
            break
        if capacity >= (count + 1) * (size // 3 + 1):
            raise RuntimeError("ulog_data_walk: output arrays full (cannot happen)")
        capacity = (count + 1) * (size // 3 + 1)
    ends = [int(result.segmentEnds[k]) for k in range(result.segments)]
    return (offsets[:result.count], types[:result.count], sizes[:result.count], ends, int(result.skipped),
            int(result.synced))


cdef size_t _text_length(const uint8_t *text, size_t limit) noexcept nogil:
    """Bytes of a NUL-padded text field before its first NUL."""
    cdef size_t k = 0
    while k < limit and text[k] != 0:
        k += 1
    return k


cdef bint _columns_are_words(const uint8_t *text, size_t length) noexcept nogil:
    """Whether ``text`` is words of ``[A-Za-z0-9_]`` joined by single commas (no empty word)."""
    cdef size_t k
    cdef size_t word = 0
    cdef uint8_t c
    for k in range(length):
        c = text[k]
        if c == 44:  # ','
            if word == 0:
                return False
            word = 0
        elif (48 <= c <= 57) or (65 <= c <= 90) or (97 <= c <= 122) or c == 95:
            word += 1
        else:
            return False
    return word > 0


def dataflash_formats(const uint8_t[::1] data, const uint64_t[::1] offsets, wanted, fields,
                      uint64_t last_walked=0xFFFFFFFFFFFFFFFF):
    """The FMT messages at ``offsets`` (in file order), checked as pymavlink's ``DFFormat`` would take them.

    Reading stops at an FMT cut off by the end of ``data`` (as pymavlink's indexer). Each FMT is checked in C:
    its format characters are ones pymavlink reads, their sizes add up to its length (bytes, header included),
    it names no more columns than it has characters, its name is ASCII without a backslash (so that names equal
    exactly when pymavlink's decoded names do) and no other type has it. A type may be defined again by a later
    FMT of the same name, length and struct codes (see ``redefined``).

    Parameters
    ----------
    wanted : collection of bytes, or None
        The names (ASCII, at most 64) whose formats are returned; the others are only checked. None: every
        type's.
    fields : sequence of bytes
        Column names (ASCII, at most 64) looked up in the wanted formats.

    Returns
    -------
    problem : str or None
        Why pymavlink's own reading is needed (the first FMT that fails a check), else None.
    formats : dict
        type → (name, length, format characters, column text, whether the column names are words of
        letters, digits and "_" joined by commas) of each wanted FMT; the characters and column text as bytes
        cut at their first NUL.
    names : dict
        name → type of the wanted names present.
    lengths : ndarray of uint64, shape (256,)
        Length of each type (bytes, header included), 0 for types no FMT defines.
    column_counts : ndarray of uint16, shape (256,)
        Columns of each type (0 for types no FMT defines).
    field_chars : ndarray of uint8, shape (256, len(fields))
        Format character of each field in each wanted type (of its last column of that name), 0 where the type
        has no such column.
    field_offsets : ndarray of int32, shape (256, len(fields))
        Byte of each field in a body (after the 3-byte header), -1 where absent.
    redefined : list of int
        The types defined again by a later FMT (each time).

    A type defined again takes the last FMT at or before byte ``last_walked`` (where pymavlink's clock set-up
    walk stopped: it reads the FMT messages it passes), else its last FMT.
    """
    cdef size_t size = data.shape[0]
    cdef size_t count = offsets.shape[0]
    cdef size_t k, j, nchars, ncolumns, ncommas, total, nfields
    cdef const uint8_t *body
    cdef int seen[256]
    cdef bint redefined
    cdef uint32_t seen_keys[256]
    cdef uint64_t taken_offsets[256]
    cdef uint8_t seen_structs[256][16]
    redefined_types = []
    cdef uint64_t slots[DATAFLASH_NAME_SLOTS]
    cdef uint32_t wanted_keys[64]
    cdef size_t nwanted = 0
    cdef uint32_t key
    cdef const char *field_names[64]
    cdef size_t field_lengths[64]
    cdef int16_t index[64]
    cdef bytes padded
    field_list = [bytes(name) for name in fields]
    nfields = len(field_list)
    if nfields > 64:
        raise ValueError("at most 64 fields")
    for k in range(nfields):
        field_names[k] = <const char *> field_list[k]
        field_lengths[k] = len(field_list[k])
    cdef bint every_type = wanted is None
    for name in (() if every_type else wanted):
        if nwanted == 64:
            raise ValueError("at most 64 wanted names")
        if len(name) > 4:  # (an FMT name has 4 bytes)
            continue
        padded = bytes(name) + b"\0\0\0\0"
        wanted_keys[nwanted] = DataFlashNameKey(<const uint8_t *> padded)
        nwanted += 1
    formats = {}
    names = {}
    lengths = np.zeros(256, dtype=np.uint64)
    column_counts = np.zeros(256, dtype=np.uint16)
    field_chars = np.zeros((256, max(nfields, 1)), dtype=np.uint8)[:, :nfields]
    field_offsets = np.full((256, max(nfields, 1)), -1, dtype=np.int32)[:, :nfields]
    cdef uint64_t[::1] length_view = lengths
    cdef unsigned short[::1] column_view = column_counts
    cdef uint8_t[:, :] char_view = field_chars
    cdef int32_t[:, :] offset_view = field_offsets
    problem = None
    memset(slots, 0, sizeof(slots))
    for k in range(256):
        seen[k] = 0
    for k in range(count):
        if offsets[k] + 89 > size:
            break
        body = &data[0] + offsets[k] + 3
        redefined = seen[body[0]]
        if redefined:
            problem = _redefinition_problem(body, &data[0] + taken_offsets[body[0]] + 3, &seen_structs[body[0]][0],
                                            seen_keys[body[0]], length_view[body[0]])
            if problem is not None:
                break
            redefined_types.append(body[0])
            if taken_offsets[body[0]] <= last_walked and offsets[k] > last_walked:
                continue  # pymavlink's clock set-up walk left the type at the FMT it read last
        seen[body[0]] = 1
        seen_keys[body[0]] = DataFlashNameKey(body + 2)
        taken_offsets[body[0]] = offsets[k]
        nchars = _text_length(body + 6, 16)
        for j in range(16):
            seen_structs[body[0]][j] = DataFlashCharStruct(body[6 + j]) if j < nchars else 0
        total = 3
        for j in range(nchars):
            if DataFlashCharSize(body[6 + j]) == 0:
                problem = f"unsupported format character {chr(body[6 + j])!r} in type {body[0]}"
                break
            total += DataFlashCharSize(body[6 + j])
        if problem is not None:
            break
        if total != body[1]:
            problem = f"type {body[0]}: length {body[1]} is not that of its format"
            break
        ncolumns = _text_length(body + 22, 64)
        ncommas = 0
        for j in range(ncolumns):
            if body[22 + j] == 44:  # ','
                ncommas += 1
        if ncolumns > 0 and ncommas + 1 > nchars:
            problem = f"type {body[0]}: more columns than format characters"
            break
        for j in range(_text_length(body + 2, 4)):
            if body[2 + j] >= 0x80 or body[2 + j] == 92:  # '\\'
                problem = f"type {body[0]}: a name that is not plain ASCII"
                break
        if problem is not None:
            break
        key = DataFlashNameKey(body + 2)
        if not redefined and DataFlashNameSeen(slots, key) != 0:  # (-1, a full table, cannot happen: 256 types)
            problem = f"two types named {body[2:2 + _text_length(body + 2, 4)]!r}"
            break
        length_view[body[0]] = body[1]
        column_view[body[0]] = ncommas + 1 if ncolumns > 0 else 0
        if not every_type:
            for j in range(nwanted):
                if wanted_keys[j] == key:
                    break
            else:
                continue
        DataFlashColumnIndexes(body + 22, ncolumns, field_names, field_lengths, nfields, index)
        for j in range(nfields):
            char_view[body[0], j] = 0  # (a redefinition replaces the earlier format's fields)
            offset_view[body[0], j] = -1
            if index[j] >= 0:
                char_view[body[0], j] = body[6 + index[j]]
                offset_view[body[0], j] = <int32_t> DataFlashFieldOffset(body + 6, <size_t> index[j])
        name = body[2:2 + _text_length(body + 2, 4)].decode("ascii")
        names[name] = body[0]
        formats[body[0]] = (name, body[1], body[6:6 + nchars], body[22:22 + ncolumns],
                            _columns_are_words(body + 22, ncolumns))
    return problem, formats, names, lengths, column_counts, field_chars, field_offsets, redefined_types


cdef _redefinition_problem(const uint8_t *body, const uint8_t *before, const uint8_t *structs, uint32_t key,
                           uint64_t length):
    """Why a second FMT (``body``) for a type defined before (its struct codes, name key and length) needs
    pymavlink's own reading, or None: pymavlink unpacks a type's messages with the struct of the first format it
    used for them and takes names and multipliers from the format its clock set-up walk read last, so only a
    format of the same name, length and struct codes is read here, and none of the types the walk reads (GPS,
    GPS2, TIME), and with a TimeUS column if and only if ``before`` (the body of the FMT taken so far) has one (the
    walk stops at the first message with one)."""
    cdef size_t j
    cdef const char *time_us = b"TimeUS"
    cdef size_t time_us_length = 6
    cdef int16_t now_index, before_index
    cdef size_t nchars = _text_length(body + 6, 16)
    if DataFlashNameKey(body + 2) != key or body[1] != length:
        return f"type {body[0]} redefined with another name or length"
    for j in range(16):
        if (DataFlashCharStruct(body[6 + j]) if j < nchars else 0) != structs[j]:
            return f"type {body[0]} redefined with other value types"
    if body[2:2 + _text_length(body + 2, 4)] in (b"GPS", b"GPS2", b"TIME"):
        return f"type {body[0]} ({body[2:5]!r}) redefined: pymavlink's clock set-up reads it"
    DataFlashColumnIndexes(body + 22, _text_length(body + 22, 64), &time_us, &time_us_length, 1, &now_index)
    DataFlashColumnIndexes(before + 22, _text_length(before + 22, 64), &time_us, &time_us_length, 1, &before_index)
    if (now_index < 0) != (before_index < 0):
        return f"type {body[0]} redefined with or without a TimeUS column"
    return None


def dataflash_columns(const uint8_t[::1] data, const uint64_t[::1] offsets, const uint8_t[::1] types,
                      const uint64_t[::1] lengths, type_ids, const uint8_t[:, :] field_chars,
                      const int32_t[:, :] field_offsets, positions, names):
    """Numeric fields of the messages of some types, grouped by type, as float64 columns (one C pass per field).

    Parameters
    ----------
    data : bytes-like
        The whole file.
    offsets, types : ndarray of uint64, ndarray of uint8
        Start and type of every message, in file order (:func:`dataflash_index`).
    lengths : ndarray of uint64, shape (256,)
        Length of each type, bytes with the header: a message of a wanted type that runs past the end of
        ``data`` (only the last message can) is not read, as pymavlink's ``recv_match``.
    type_ids : sequence of int
        The types wanted; the messages of other types are dropped.
    field_chars, field_offsets : ndarrays of shape (256, fields)
        Of :func:`dataflash_formats`: each field's format character (0: absent) and byte in a body.
    positions : sequence of int
        The fields (columns of ``field_chars``) to read (at most 64).
    names : sequence of str
        The name of each of ``positions`` (the keys of the columns).

    Returns
    -------
    dict
        type → (offsets of its messages in file order, dict name → ndarray of float64: the values pymavlink
        gives converted to float, multipliers applied, of each field the type has as a number, the name of the
        first field it has as text or half float or None). Absent: the wanted types without messages.
    """
    cdef size_t count = offsets.shape[0]
    cdef uint64_t counts[256]
    cdef uint64_t *rows[256]
    cdef uint64_t[::1] offset_view
    cdef double[::1] value_view
    cdef size_t k, position, type_id, last
    cdef uint8_t char
    if types.shape[0] != offsets.shape[0] or lengths.shape[0] != 256:
        raise ValueError("offsets and types must have one length, lengths 256 entries")
    if field_chars.shape[0] != 256 or field_offsets.shape[0] != 256 or \
            field_chars.shape[1] != field_offsets.shape[1]:
        raise ValueError("field_chars and field_offsets must be (256, fields) tables")
    if len(names) != len(positions):
        raise ValueError("one name per position")
    cdef size_t npositions = len(positions)
    cdef size_t field_position[64]
    cdef size_t j
    if npositions > 64:
        raise ValueError("at most 64 positions")
    for j in range(npositions):
        field_position[j] = positions[j]
        if field_position[j] >= <size_t> field_chars.shape[1]:
            raise ValueError(f"position {positions[j]} out of range")
    if count == 0:
        return {}
    ScanCountTypes(&types[0], count, counts)
    for k in range(256):
        rows[k] = NULL
    out = {}
    last = types[count - 1]
    if offsets[count - 1] + lengths[last] > <uint64_t> data.shape[0]:
        # cut off by the end (only the last message can be): not read
        counts[last] -= 1
        count -= 1
    for type_id in type_ids:
        if type_id >= 256:
            raise ValueError(f"type {type_id} out of range")
        if counts[type_id] == 0 or type_id in out:
            continue
        mine = np.empty(counts[type_id], dtype=np.uint64)
        offset_view = mine
        rows[type_id] = &offset_view[0]
        out[type_id] = mine
    DataFlashSplit(&offsets[0], &types[0], count, rows)
    cdef size_t present, row
    for type_id, mine in out.items():
        offset_view = mine
        columns = {}
        unreadable = None
        present = 0
        for j in range(npositions):
            present += field_chars[type_id, field_position[j]] != 0
        block = np.empty((present, offset_view.shape[0]), dtype=np.float64)  # one row per field the type has
        row = 0
        for j in range(npositions):
            position = field_position[j]
            char = field_chars[type_id, position]
            if char == 0:
                continue
            name = names[j]
            values = block[row]
            row += 1
            value_view = values
            status = DataFlashColumn(&data[0], data.shape[0], &offset_view[0], offset_view.shape[0],
                                     <size_t> field_offsets[type_id, position], char, &value_view[0])
            if status == DataFlashColumnOutside:
                raise ValueError(f"type {type_id}: a message runs past the end of the data")
            if status == DataFlashColumnNotNumeric:
                if unreadable is None:
                    unreadable = name
                continue
            columns[name] = values
        out[type_id] = (mine, columns, unreadable)
    return out


def ulog_format_names(const uint8_t[::1] data, const uint64_t[::1] offsets, const unsigned short[::1] sizes):
    """The name of each F (format) message at ``offsets`` whose parsing by pyulog surely succeeds, else None.

    Surely succeeds (``ULogFormatNameLength``): ASCII, a ``:`` after the name, and every non-empty
    ``;``-separated item of the field list a type and a name separated by a space, with an array size of 1 to 4
    digits if the type has ``[``. The others (None) are for the caller to parse in Python, where an exception
    means pyulog flags corruption.
    """
    cdef size_t count = offsets.shape[0]
    cdef int inside
    cdef size_t k
    if sizes.shape[0] != offsets.shape[0]:
        raise ValueError("offsets and sizes must have one length")
    if count == 0:
        return []
    lengths = np.empty(count, dtype=np.uintp)
    cdef size_t[::1] length_view = lengths
    with nogil:
        inside = ULogFormatNameLengths(&data[0], data.shape[0], &offsets[0], &sizes[0], count, &length_view[0])
    if not inside:
        raise ValueError("a message runs past the end of the data")
    names = []
    for k in range(count):
        if length_view[k] > sizes[k]:
            names.append(None)
        else:
            names.append(bytes(data[offsets[k] + 3:offsets[k] + 3 + length_view[k]]).decode("ascii"))
    return names


cdef extern from "_ulog_scan.h":
    size_t ULogCheckMessages(const uint8_t *data, const uint64_t *offsets, const uint8_t *types,
                             const unsigned short *sizes, size_t count, uint8_t *failed, size_t *undecided,
                             size_t capacity) nogil
    size_t ULogCheckAndCount(const uint8_t *data, const uint64_t *offsets, const uint8_t *types,
                             const unsigned short *sizes, size_t count, const ULogSubscriptions *subscriptions,
                             uint64_t *counts, unsigned short *sampleSlots, uint8_t *failed, size_t *undecided,
                             size_t capacity) nogil
    void ULogCopySamples(const uint8_t *data, const uint64_t *offsets, const unsigned short *sampleSlots,
                         size_t count, const uint64_t *itemsizes, uint8_t **rows) nogil

from cpython.bytes cimport PyBytes_AS_STRING, PyBytes_FromStringAndSize


def ulog_typed_messages(const uint8_t[::1] data, const uint64_t[::1] offsets, const uint8_t[::1] types,
                        const unsigned short[::1] sizes, uint8_t wanted):
    """The messages of type ``wanted`` among those at ``offsets`` (types, payload sizes): their whole bytes
    (3-byte header and payload) joined in order, the bytes of what they define (the F messages of one firmware,
    the A messages of a segment) that a cache keys on, and the byte offset of each. Each header holds its
    payload size, so two lists of messages give equal bytes only if they are equal message by message.
    """
    cdef size_t count = offsets.shape[0]
    cdef size_t total = 0
    cdef size_t k, outside, length
    cdef char *out
    if types.shape[0] != offsets.shape[0] or sizes.shape[0] != offsets.shape[0]:
        raise ValueError("offsets, types and sizes must have one length")
    if count == 0:
        return b"", []
    with nogil:
        outside = ULogFirstOutside(data.shape[0], &offsets[0], &sizes[0], count)
    if outside < count:
        raise ValueError(f"the message at byte {offsets[outside]} runs past the end of the data")
    starts = []
    for k in range(count):
        if types[k] == wanted:
            total += 3 + sizes[k]
            starts.append(offsets[k])
    joined = PyBytes_FromStringAndSize(NULL, total)
    out = PyBytes_AS_STRING(joined)
    with nogil:
        for k in range(count):
            if types[k] == wanted:
                length = 3 + sizes[k]
                memcpy(out, &data[offsets[k]], length)
                out += length
    return joined, starts


def ulog_message_checks(const uint8_t[::1] data, const uint64_t[::1] offsets, const uint8_t[::1] types,
                        const unsigned short[::1] sizes):
    """The messages pyulog would fail to parse, in one pass of ``ULogCheckMessages`` (each message wholly inside
    ``data``).

    An L, C, A or D message shorter than 9, 11, 3 or 2 bytes, an O (dropout) message not of 2 bytes, and an
    I/M/P/Q message that ``ULogCheckInfo`` fails (from byte 1 for M and Q) make pyulog raise.

    Returns
    -------
    failing : bytes
        The types (letters, each once, in ``b"LCADOIMPQ"`` order) of which some message fails.
    undecided : list of int
        Indices of the I/M/P/Q messages whose key is not ASCII (pyulog drops undecodable bytes first): for
        the caller to check in Python.
    """
    cdef size_t count = offsets.shape[0]
    cdef size_t outside
    cdef size_t found = 0
    cdef uint8_t failed[256]
    cdef size_t first[64]
    if types.shape[0] != offsets.shape[0] or sizes.shape[0] != offsets.shape[0]:
        raise ValueError("offsets, types and sizes must have one length")
    if count == 0:
        return b"", []
    memset(failed, 0, sizeof(failed))
    with nogil:
        outside = ULogFirstOutside(data.shape[0], &offsets[0], &sizes[0], count)
        if outside == count:
            found = ULogCheckMessages(&data[0], &offsets[0], &types[0], &sizes[0], count, failed, first, 64)
    if outside < count:
        raise ValueError(f"the message at byte {offsets[outside]} runs past the end of the data")
    failing = bytes([letter for letter in b"LCADOIMPQ" if failed[letter]])
    if found <= 64:
        return failing, [int(first[k]) for k in range(found)]
    every = np.empty(found, dtype=np.uintp)  # more than 64: walk again with room for each
    cdef size_t[::1] every_view = every
    memset(failed, 0, sizeof(failed))
    with nogil:
        ULogCheckMessages(&data[0], &offsets[0], &types[0], &sizes[0], count, failed, &every_view[0], found)
    return failing, every.tolist()


def ulog_format_fields(bytes payload, size_t name_length):
    """The fields of an F (format) message that :func:`ulog_format_names` vouched for (its name
    ``name_length`` bytes): [(type, array size, field name), …], what pyulog's parse gives (the field list is
    the text between the first and the next ``:``, its items split at ``;``, each item's type and name its first
    two words split at a space, the array size the digits in the type's brackets, 0 without)."""
    cdef const char *text = payload
    cdef size_t size = len(payload)
    cdef size_t end, item, stop, space, word_end, at, close, k, count
    if name_length >= size or text[name_length] != b':':
        raise ValueError("payload: no ':' after the name")
    end = name_length + 1
    while end < size and text[end] != b':':
        end += 1
    fields = []
    item = name_length + 1
    while item <= end:
        stop = item
        while stop < end and text[stop] != b';':
            stop += 1
        if stop > item:
            space = item
            while space < stop and text[space] != b' ':
                space += 1
            if space == stop:
                raise ValueError("payload: an item without a space (not vouched for)")
            word_end = space + 1
            while word_end < stop and text[word_end] != b' ':
                word_end += 1
            at = item
            while at < space and text[at] != b'[':
                at += 1
            count = 0
            if at < space:
                close = at + 1
                while close < space and text[close] != b']':
                    count = count * 10 + <size_t> (text[close] - 48)
                    close += 1
            fields.append((text[item:at].decode("ascii"), count, text[space + 1:word_end].decode("ascii")))
        item = stop + 1
    return fields


def ulog_split_messages(bytes joined):
    """The whole messages of ``joined`` (from :func:`ulog_typed_messages`): the byte offset of each 3-byte header
    and its payload size (bytes), as lists; ValueError if the last one is cut."""
    cdef const unsigned char *text = joined
    cdef size_t size = len(joined)
    cdef size_t at = 0, length
    offsets, sizes = [], []
    while at < size:
        if size - at < 3:
            raise ValueError("joined: a header is cut")
        length = <size_t> text[at] | (<size_t> text[at + 1] << 8)
        if size - at - 3 < length:
            raise ValueError("joined: a payload is cut")
        offsets.append(at)
        sizes.append(length)
        at += 3 + length
    return offsets, sizes


def ulog_subscriptions(bytes joined):
    """The A (subscription) messages of ``joined`` (from :func:`ulog_typed_messages`, each of at least 3 bytes):
    (msg_id, multi_id, topic name) of each, the name decoded as pyulog decodes it (UTF-8, undecodable bytes
    dropped)."""
    cdef const unsigned char *text = joined
    cdef size_t size = len(joined)
    cdef size_t at = 0, length
    out = []
    while at < size:
        if size - at < 3:
            raise ValueError("joined: a header is cut")
        length = <size_t> text[at] | (<size_t> text[at + 1] << 8)
        if size - at - 3 < length or length < 3:
            raise ValueError("joined: a payload is cut or shorter than 3 bytes")
        out.append((<size_t> text[at + 4] | (<size_t> text[at + 5] << 8), text[at + 3],
                    joined[at + 6:at + 3 + length].decode("utf-8", "ignore")))
        at += 3 + length
    return out


def ulog_checked_tables(const uint8_t[::1] data, const uint64_t[::1] offsets, const uint8_t[::1] types,
                        const unsigned short[::1] sizes, subscriptions):
    """:func:`ulog_message_checks` and :func:`ulog_data_tables` of one segment's messages in one pass over them
    (``ULogCheckAndCount``), then the samples copied (``ULogCopySamples``: only the samples' bytes are read
    again).

    Returns
    -------
    tables : list of ndarray of uint8, shape (count, itemsize)
        As :func:`ulog_data_tables`.
    failing, undecided
        As :func:`ulog_message_checks`.
    """
    cdef size_t count = offsets.shape[0]
    cdef size_t nsub = len(subscriptions)
    cdef size_t k, outside, found = 0
    cdef uint8_t failed[256]
    cdef size_t first[64]
    cdef ULogSubscriptions wanted
    cdef uint8_t **rows
    cdef uint8_t[:, ::1] view
    if types.shape[0] != offsets.shape[0] or sizes.shape[0] != offsets.shape[0]:
        raise ValueError("offsets, types and sizes must have one length")
    if nsub >= 65535:
        raise ValueError("too many subscriptions")
    if count > 0:
        with nogil:
            outside = ULogFirstOutside(data.shape[0], &offsets[0], &sizes[0], count)
        if outside < count:
            raise ValueError(f"the message at byte {offsets[outside]} runs past the end of the data")
    slots = np.zeros(65536, dtype=np.uint16)  # slot + 1 of each msg_id (0: not asked for)
    starts = np.zeros(nsub + 1, dtype=np.uint64)
    itemsizes = np.zeros(nsub + 1, dtype=np.uint64)
    for k, (msg_id, start, itemsize) in enumerate(subscriptions):
        if not 0 <= msg_id < 65536 or slots[msg_id] != 0:
            raise ValueError(f"msg_id {msg_id} out of range or given twice")
        slots[msg_id], starts[k], itemsizes[k] = k + 1, start, itemsize
    cdef const unsigned short[::1] slot_view = slots
    cdef const uint64_t[::1] start_view = starts
    cdef const uint64_t[::1] itemsize_view = itemsizes
    wanted.slotOf = &slot_view[0]
    wanted.starts = &start_view[0]
    wanted.itemsizes = &itemsize_view[0]
    counts = np.zeros(nsub + 1, dtype=np.uint64)
    sample_slots = np.empty(count + 1, dtype=np.uint16)
    cdef uint64_t[::1] count_of = counts
    cdef unsigned short[::1] sample_view = sample_slots
    memset(failed, 0, sizeof(failed))
    if count > 0:
        with nogil:
            found = ULogCheckAndCount(&data[0], &offsets[0], &types[0], &sizes[0], count, &wanted, &count_of[0],
                                      &sample_view[0], failed, first, 64)
    failing = bytes([letter for letter in b"LCADOIMPQ" if failed[letter]])
    if found <= 64:
        undecided = [int(first[k]) for k in range(found)]
    else:  # more than 64: checked again with room for each
        undecided = ulog_message_checks(data, offsets, types, sizes)[1]
    tables = [np.empty((count_of[k], itemsizes[k]), dtype=np.uint8) for k in range(nsub)]
    rows = <uint8_t **> PyMem_Malloc((nsub + 1) * sizeof(uint8_t *))
    if rows == NULL:
        raise MemoryError()
    try:
        for k in range(nsub):
            rows[k] = NULL
            if count_of[k] > 0 and itemsizes[k] > 0:
                view = tables[k]
                rows[k] = &view[0, 0]
        if count > 0:
            with nogil:
                ULogCopySamples(&data[0], &offsets[0], &sample_view[0], count, &itemsize_view[0], rows)
    finally:
        PyMem_Free(rows)
    return tables, failing, undecided
