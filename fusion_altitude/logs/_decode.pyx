# cython: boundscheck=False, wraparound=False
"""The fast log decoders' C loops. DataFlash (:mod:`fusion_altitude.logs._dataflash_fast`): the message index
(``_dataflash_scan.h``), the FMT messages checked and read, the bodies of the asked-for types grouped by type.
ULog (:mod:`fusion_altitude.logs._ulog_fast`): the message walk (``_ulog_scan.h``), the info/parameter and format
checks, the samples of each subscription gathered from the data section."""

import numpy as np

from libc.stdint cimport int16_t, int32_t, uint8_t, uint32_t, uint64_t
from libc.math cimport NAN
from libc.string cimport memcpy, memset
from cpython.mem cimport PyMem_Calloc, PyMem_Free, PyMem_Malloc

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
    void DataFlashCountTypes(const uint8_t *types, size_t count, size_t *counts) nogil
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
    lengths = np.array([result.lengths[k] for k in range(256)], dtype=np.uint8)
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
    ctypedef struct ULogScanResult:
        size_t count
        size_t endOffset
        int full
    void ULogScan(const uint8_t *data, size_t size, size_t start, uint64_t *offsets, uint8_t *types,
                  unsigned short *sizes, size_t capacity, ULogScanResult *result) nogil


def ulog_index(const uint8_t[::1] data, size_t start=16):
    """Where each whole message of a ULog starts (from byte ``start``), its type and payload size, in one pass.

    Returns
    -------
    offsets : ndarray of uint64
        Byte offset of each message's 3-byte header.
    types : ndarray of uint8
        Message type (``ord('D')`` for data, …).
    sizes : ndarray of uint16
        Payload size of each, bytes.
    end : int
        Byte after the last whole message (a cut message after it is not read, as pyulog).
    """
    cdef size_t size = data.shape[0]
    cdef size_t capacity = (size - start) // 3 + 1 if size > start else 1
    offsets = np.empty(capacity, dtype=np.uint64)
    types = np.empty(capacity, dtype=np.uint8)
    sizes = np.empty(capacity, dtype=np.uint16)
    cdef uint64_t[::1] offsets_view = offsets
    cdef uint8_t[::1] types_view = types
    cdef unsigned short[::1] sizes_view = sizes
    cdef ULogScanResult result
    if size <= start:
        return offsets[:0], types[:0], sizes[:0], int(start)
    with nogil:
        ULogScan(&data[0], size, start, &offsets_view[0], &types_view[0], &sizes_view[0], capacity, &result)
    if result.full:
        raise RuntimeError("ulog_index: output arrays full (cannot happen: capacity covers 3-byte messages)")
    return offsets[:result.count], types[:result.count], sizes[:result.count], int(result.endOffset)


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
        for j in range(16):
            seen_structs[body[0]][j] = DataFlashCharStruct(body[6 + j]) if j < _text_length(body + 6, 16) else 0
        nchars = _text_length(body + 6, 16)
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
        The fields (columns of ``field_chars``) to read.
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
    cdef size_t counts[256]
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
    for position in positions:
        if position >= <size_t> field_chars.shape[1]:
            raise ValueError(f"position {position} out of range")
    if count == 0:
        return {}
    DataFlashCountTypes(&types[0], count, counts)
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
    for type_id, mine in out.items():
        offset_view = mine
        columns = {}
        unreadable = None
        for position, name in zip(positions, names):
            char = field_chars[type_id, position]
            if char == 0:
                continue
            values = np.empty(offset_view.shape[0], dtype=np.float64)
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


# pyulog's basic type names and their sizes (bytes), for the info and parameter checks.
_ULOG_TYPE_SIZES = {b"int8_t": 1, b"uint8_t": 1, b"int16_t": 2, b"uint16_t": 2, b"int32_t": 4, b"uint32_t": 4,
                    b"int64_t": 8, b"uint64_t": 8, b"float": 4, b"double": 8, b"bool": 1, b"char": 1}


def ulog_infos_ok(const uint8_t[::1] data, const uint64_t[::1] offsets, const unsigned short[::1] sizes,
                  size_t skip):
    """Whether pyulog parses the I/M/P/Q messages at ``offsets`` without an exception.

    Each payload (``sizes`` bytes after a message's 3-byte header, from byte ``skip``: 1 for M and Q, whose
    first byte pyulog skips) must hold a key length, a key of at least two words (type, name) and, for a basic
    type, a value of exactly that type's size.

    Returns
    -------
    ok : bool
        False if some message surely makes pyulog raise.
    undecided : list of int
        Indices of the messages whose key is not ASCII (pyulog drops undecodable bytes first): for the caller to
        check in Python.
    """
    cdef size_t count = offsets.shape[0]
    cdef size_t k, j, available, space
    cdef const uint8_t *payload
    cdef size_t key_length
    cdef bint ascii
    undecided = []
    for k in range(count):
        if sizes[k] < 1 + skip or offsets[k] + 3 + sizes[k] > <uint64_t> data.shape[0]:
            return False, undecided
        payload = &data[0] + offsets[k] + 3 + skip
        available = sizes[k] - skip  # bytes of the payload pyulog reads
        key_length = payload[0]
        if key_length > available - 1:
            key_length = available - 1
        ascii = True
        space = key_length
        for j in range(key_length):
            if payload[1 + j] >= 0x80:
                ascii = False
                break
            if payload[1 + j] == 32 and space == key_length:
                space = j
        if not ascii:
            undecided.append(k)
            continue
        if space == key_length:  # one word: pyulog's split(" ") gives no name
            return False, undecided
        kind = payload[1:1 + space]
        if kind.startswith(b"char["):
            continue
        kind_size = _ULOG_TYPE_SIZES.get(kind)
        if kind_size is not None and <long> available - 1 - <long> payload[0] != <long> kind_size:
            return False, undecided
    return True, undecided


cdef size_t _find(const uint8_t *text, size_t length, uint8_t wanted) noexcept nogil:
    """Index of the first ``wanted`` byte of ``text[0 .. length)``, or ``length`` if there is none."""
    cdef size_t k
    for k in range(length):
        if text[k] == wanted:
            return k
    return length


cdef bint _ulog_field_simple(const uint8_t *item, size_t length) noexcept nogil:
    """Whether one ``type name`` item of a format parses in pyulog without an exception, surely: a space after
    the type, and an array size (if any) of 1 to 4 digits closed by ``]``."""
    cdef size_t space = _find(item, length, 32)
    cdef size_t k, at, close
    if space == length:
        return False
    at = _find(item, space, 91)  # '['
    if at == space:
        return True
    close = _find(item, space, 93)  # ']'
    if close == space or close <= at + 1 or close > at + 5:  # (no "]": pyulog's slice would end at -1)
        return False
    for k in range(at + 1, close):
        if not (48 <= item[k] <= 57):
            return False
    return True


def ulog_format_names(const uint8_t[::1] data, const uint64_t[::1] offsets, const unsigned short[::1] sizes):
    """The name of each F (format) message at ``offsets`` whose parsing by pyulog surely succeeds, else None.

    Surely succeeds: ASCII, a ``:`` after the name, and every non-empty ``;``-separated item of the field list
    a type and a name separated by a space, with an array size of 1 to 4 digits if the type has ``[``. The
    others (None) are for the caller to parse in Python, where an exception means pyulog flags corruption.
    """
    cdef size_t count = offsets.shape[0]
    cdef size_t k, j, colon, end, item
    cdef const uint8_t *payload
    cdef size_t size
    cdef bint simple
    names = []
    for k in range(count):
        if offsets[k] + 3 + sizes[k] > <uint64_t> data.shape[0]:
            raise ValueError(f"the message at byte {offsets[k]} runs past the end of the data")
        payload = &data[0] + offsets[k] + 3
        size = sizes[k]
        simple = True
        colon = size
        for j in range(size):
            if payload[j] >= 0x80:
                simple = False
                break
            if payload[j] == 58 and colon == size:  # ':'
                colon = j
        if not simple or colon == size:
            names.append(None)
            continue
        end = colon + 1
        while end < size and payload[end] != 58:
            end += 1
        item = colon + 1
        for j in range(colon + 1, end + 1):
            if j == end or payload[j] == 59:  # ';' or the end of the field list
                if j > item and not _ulog_field_simple(payload + item, j - item):
                    simple = False
                    break
                item = j + 1
        names.append(payload[:colon].decode("ascii") if simple else None)
    return names


def ulog_type_counts(const uint8_t[::1] types):
    """How many messages of each type (ndarray of int64, shape (256,)), in one pass."""
    counts = np.zeros(256, dtype=np.int64)
    cdef long long[::1] view = counts
    cdef Py_ssize_t k
    for k in range(types.shape[0]):
        view[types[k]] += 1
    return counts


def ulog_first_of(const uint8_t[::1] types, bytes wanted):
    """Index of the first message whose type is one of the bytes of ``wanted``, or the count if none."""
    cdef bint hit[256]
    cdef Py_ssize_t k
    for k in range(256):
        hit[k] = False
    for k in range(len(wanted)):
        hit[<uint8_t> wanted[k]] = True
    for k in range(types.shape[0]):
        if hit[types[k]]:
            return k
    return types.shape[0]


def ulog_data_tables(const uint8_t[::1] data, const uint64_t[::1] offsets, const uint8_t[::1] types,
                     const unsigned short[::1] sizes, subscriptions):
    """The data messages of each subscription, gathered in one pass, as pyulog reads them.

    Parameters
    ----------
    data : bytes-like
        The whole file.
    offsets, types, sizes : ndarrays
        Start, type and payload size (bytes) of each message of the data section (each wholly inside ``data``).
    subscriptions : sequence of (msg_id, offset, itemsize)
        Per subscription, its msg_id (each at most once), the offset of its A message (only later data
        messages count) and the bytes of one sample (a data message of another size is not one of its samples).

    Returns
    -------
    list of ndarray of uint8, shape (count, itemsize)
        Per subscription, the payloads after the 2-byte msg_id of its data messages, in file order.
    """
    if types.shape[0] != offsets.shape[0] or sizes.shape[0] != offsets.shape[0]:
        raise ValueError("offsets, types and sizes must have one length")
    # slot + 1 of each msg_id (0: not asked for); calloc'd, so only the pages of the msg_ids used are touched
    cdef unsigned short *slot_of = <unsigned short *> PyMem_Calloc(65536, sizeof(unsigned short))
    if slot_of == NULL:
        raise MemoryError()
    try:
        return _ulog_data_tables(data, offsets, types, sizes, subscriptions, slot_of)
    finally:
        PyMem_Free(slot_of)


cdef _ulog_data_tables(const uint8_t[::1] data, const uint64_t[::1] offsets, const uint8_t[::1] types,
                       const unsigned short[::1] sizes, subscriptions, unsigned short *slot_of):
    """:func:`ulog_data_tables` with its msg_id table (``slot_of``, zeroed) allocated."""
    cdef size_t count = offsets.shape[0]
    cdef size_t nsub = len(subscriptions)
    cdef size_t k, slot, msg_id
    if nsub >= 65535:
        raise ValueError("too many subscriptions")
    starts = np.zeros(nsub + 1, dtype=np.uint64)
    itemsizes = np.zeros(nsub + 1, dtype=np.uint64)
    counts = np.zeros(nsub + 1, dtype=np.uint64)
    cdef uint64_t[::1] start_of = starts
    cdef uint64_t[::1] itemsize_of = itemsizes
    cdef uint64_t[::1] count_of = counts
    for k, (msg_id_value, start, itemsize) in enumerate(subscriptions):
        if not 0 <= msg_id_value < 65536 or slot_of[msg_id_value] != 0:
            raise ValueError(f"msg_id {msg_id_value} out of range or given twice")
        slot_of[msg_id_value] = k + 1
        start_of[k] = start
        itemsize_of[k] = itemsize
    for k in range(count):
        if offsets[k] + 3 + sizes[k] > <uint64_t> data.shape[0]:
            raise ValueError(f"the message at byte {offsets[k]} runs past the end of the data")
    with nogil:
        for k in range(count):
            if types[k] != 68 or sizes[k] < 2:  # 'D'
                continue
            msg_id = data[offsets[k] + 3] | (<size_t> data[offsets[k] + 4] << 8)
            if slot_of[msg_id] == 0:
                continue
            slot = <size_t> slot_of[msg_id] - 1
            if offsets[k] > start_of[slot] and <uint64_t> sizes[k] - 2 == itemsize_of[slot]:
                count_of[slot] += 1
    tables = [np.empty((count_of[k], itemsize_of[k]), dtype=np.uint8) for k in range(nsub)]
    cdef uint8_t **rows = <uint8_t **> PyMem_Malloc((nsub + 1) * sizeof(uint8_t *))
    cdef uint8_t[:, ::1] view
    if rows == NULL:
        raise MemoryError()
    try:
        for k in range(nsub):
            rows[k] = NULL
            if count_of[k] > 0 and itemsize_of[k] > 0:
                view = tables[k]
                rows[k] = &view[0, 0]
        with nogil:
            for k in range(count):
                if types[k] != 68 or sizes[k] < 2:
                    continue
                msg_id = data[offsets[k] + 3] | (<size_t> data[offsets[k] + 4] << 8)
                if slot_of[msg_id] == 0:
                    continue
                slot = <size_t> slot_of[msg_id] - 1
                if rows[slot] != NULL and offsets[k] > start_of[slot] and \
                        <uint64_t> sizes[k] - 2 == itemsize_of[slot]:
                    memcpy(rows[slot], &data[0] + offsets[k] + 5, itemsize_of[slot])
                    rows[slot] += itemsize_of[slot]
    finally:
        PyMem_Free(rows)
    return tables
