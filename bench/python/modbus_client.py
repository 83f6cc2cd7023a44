"""Python peer for the round-trip benchmark: COUNT reads of two holding registers.

Usage: modbus_client.py LIBRARY PORT BAUD COUNT ADDRESS HIGH LOW
LIBRARY is pymodbus or minimalmodbus. Reads holding registers ADDRESS and ADDRESS+1 of
station 1 and checks every reply holds HIGH and LOW. Prints one JSON object: the library
and the latency of every read in nanoseconds.
"""
import json
import sys
import time


def pymodbus_reader(port: str, baud: int):
    import pymodbus
    from pymodbus import FramerType
    from pymodbus.client import ModbusSerialClient

    client = ModbusSerialClient(port, framer=FramerType.RTU, baudrate=baud, parity="N", stopbits=1, bytesize=8, timeout=1, retries=0)
    if not client.connect():
        raise SystemExit(f"cannot open {port}")

    def read(address: int):
        reply = client.read_holding_registers(address, count=2, device_id=1)
        if reply.isError():
            raise SystemExit(f"error reply: {reply}")
        return reply.registers

    return f"pymodbus {pymodbus.__version__}", read


def minimalmodbus_reader(port: str, baud: int):
    import minimalmodbus
    import serial

    instrument = minimalmodbus.Instrument(port, 1, mode=minimalmodbus.MODE_RTU)
    instrument.serial.baudrate = baud
    instrument.serial.parity = serial.PARITY_NONE
    instrument.serial.timeout = 1
    instrument.clear_buffers_before_each_transaction = False

    def read(address: int):
        return instrument.read_registers(address, 2, functioncode=3)

    return f"minimalmodbus {minimalmodbus.__version__}", read


def main() -> None:
    library, port = sys.argv[1], sys.argv[2]
    baud, count, address, high, low = (int(a) for a in sys.argv[3:8])
    name, read = (pymodbus_reader if library == "pymodbus" else minimalmodbus_reader)(port, baud)
    expected = [high, low]
    for _ in range(20):
        values = read(address)
        if list(values) != expected:
            raise SystemExit(f"read {values}, expected {expected}")
    latencies = []
    for _ in range(count):
        start = time.perf_counter_ns()
        values = read(address)
        latencies.append(time.perf_counter_ns() - start)
        if list(values) != expected:
            raise SystemExit(f"read {values}, expected {expected}")
    print(json.dumps({"client": name, "latencies_ns": latencies}))


if __name__ == "__main__":
    main()
