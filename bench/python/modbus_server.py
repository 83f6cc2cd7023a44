"""Modbus RTU server for the round-trip benchmark: pymodbus holding registers on a serial port.

Usage: modbus_server.py PORT BAUD ADDRESS HIGH LOW
Station 1 (pymodbus answers every station): holding registers ADDRESS and ADDRESS+1 hold
HIGH and LOW, every other holding register at address A holds A mod 65536. Prints "ready"
once configured.
"""
import logging
import sys

from pymodbus import FramerType
from pymodbus.datastore import ModbusDeviceContext, ModbusSequentialDataBlock, ModbusServerContext
from pymodbus.server import StartSerialServer


def main() -> None:
    port = sys.argv[1]
    baud, address, high, low = (int(a) for a in sys.argv[2:6])
    logging.disable(logging.CRITICAL)
    values = [a % 65536 for a in range(max(8192, address + 2))]
    values[address], values[address + 1] = high, low
    # pymodbus numbers blocks from 1 and adds 1 to wire addresses: position k answers address k.
    block = ModbusSequentialDataBlock(1, values)
    context = ModbusServerContext(devices=ModbusDeviceContext(hr=block), single=True)
    print("ready", flush=True)
    StartSerialServer(context, framer=FramerType.RTU, port=port, baudrate=baud, parity="N", stopbits=1, bytesize=8)


if __name__ == "__main__":
    main()
