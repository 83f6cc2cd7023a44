"""Independent Modbus RTU masters for tests/tests/modbus_peer_master.rs: pymodbus's client or
minimalmodbus acts as the master against our virtual drive on a serial port.

Usage: modbus_peer_client.py (pymodbus|minimalmodbus) PORT STATION [rtu|ascii] < plan.json
PORT may be tcp://HOST:PORT (pymodbus only): its TCP client with the RTU (or ASCII) framer,
as for a serial device server (tests/tests/tcp.rs, cli/tests/tcp.rs).
The plan is a JSON list of operations:
  {"op": "read", "address": A, "count": N}        function 03
  {"op": "write", "address": A, "value": V}       function 06
  {"op": "write_many", "address": A, "values": [...]}  function 16
  {"op": "read_coils", "address": A, "count": N}  function 01
  {"op": "write_coil", "address": A, "value": true|false}  function 05
  {"op": "write_coils", "address": A, "values": [true|false, ...]}  function 15
  {"op": "echo", "value": V}                      function 08, sub-function 0000h (V echoed)
  {"op": "read_discrete", "address": A, "count": N}  function 02
  {"op": "read_input", "address": A, "count": N}  function 04
  {"op": "device_info"}                           function 2Bh / 0Eh, basic identification
  {"op": "sleep", "seconds": S}
One JSON line is printed per operation: {"ok": true, "values": [...]} or
{"ok": false, "exception": CODE} for a Modbus exception reply, or {"ok": false, "error": TEXT}.
"""
import json
import logging
import sys
import time


def run_pymodbus(port, station, plan, mode):
    from pymodbus import FramerType
    from pymodbus.client import ModbusSerialClient
    from pymodbus.pdu import ExceptionResponse

    framer = FramerType.ASCII if mode == "ascii" else FramerType.RTU
    if port.startswith("tcp://"):
        # A serial device server: the serial line's frames over TCP, no MBAP header.
        from pymodbus.client import ModbusTcpClient

        host, _, number = port[len("tcp://"):].rpartition(":")
        client = ModbusTcpClient(host, port=int(number), framer=framer, timeout=1, retries=0)
    else:
        client = ModbusSerialClient(port, framer=framer, baudrate=115200, parity="N",
                                    stopbits=1, bytesize=8, timeout=1, retries=0)
    if not client.connect():
        raise SystemExit(f"cannot open {port}")

    def answer(response, values):
        if isinstance(response, ExceptionResponse) or response.isError():
            return {"ok": False, "exception": getattr(response, "exception_code", None)}
        return {"ok": True, "values": values(response)}

    for step in plan:
        op = step["op"]
        try:
            if op == "sleep":
                time.sleep(step["seconds"])
                result = {"ok": True, "values": []}
            elif op == "read":
                r = client.read_holding_registers(step["address"], count=step["count"], device_id=station)
                result = answer(r, lambda r: list(r.registers))
            elif op == "write":
                r = client.write_register(step["address"], step["value"], device_id=station)
                result = answer(r, lambda r: [r.registers[0]] if getattr(r, "registers", None) else [])
            elif op == "write_many":
                r = client.write_registers(step["address"], step["values"], device_id=station)
                result = answer(r, lambda r: [])
            elif op == "echo":
                r = client.diag_query_data(step["value"].to_bytes(2, "big"), device_id=station)
                result = answer(r, lambda r: [int.from_bytes(r.message, "big")])
            elif op == "read_discrete":
                r = client.read_discrete_inputs(step["address"], count=step["count"], device_id=station)
                result = answer(r, lambda r: [int(b) for b in r.bits[: step["count"]]])
            elif op == "read_input":
                r = client.read_input_registers(step["address"], count=step["count"], device_id=station)
                result = answer(r, lambda r: list(r.registers))
            elif op == "device_info":
                r = client.read_device_information(read_code=1, object_id=0, device_id=station)
                result = answer(r, lambda r: [])
            elif op == "read_coils":
                r = client.read_coils(step["address"], count=step["count"], device_id=station)
                result = answer(r, lambda r: [int(b) for b in r.bits[: step["count"]]])
            elif op == "write_coil":
                r = client.write_coil(step["address"], step["value"], device_id=station)
                result = answer(r, lambda r: [])
            elif op == "write_coils":
                r = client.write_coils(step["address"], step["values"], device_id=station)
                result = answer(r, lambda r: [])
            else:
                result = {"ok": False, "error": f"unknown op {op}"}
        except Exception as error:  # a timeout or a garbled reply: report it, go on
            result = {"ok": False, "error": f"{type(error).__name__}: {error}"}
        print(json.dumps(result), flush=True)
    client.close()


def run_minimalmodbus(port, station, plan, mode):
    import minimalmodbus

    framing = minimalmodbus.MODE_ASCII if mode == "ascii" else minimalmodbus.MODE_RTU
    instrument = minimalmodbus.Instrument(port, station, mode=framing)
    instrument.serial.baudrate = 115200
    instrument.serial.parity = "N"
    instrument.serial.stopbits = 1
    instrument.serial.bytesize = 8
    instrument.serial.timeout = 1
    instrument.clear_buffers_before_each_transaction = True
    codes = {
        "illegal function": 1,
        "illegal data address": 2,
        "illegal data value": 3,
        "device failure": 4,
    }
    for step in plan:
        op = step["op"]
        try:
            if op == "sleep":
                time.sleep(step["seconds"])
                values = []
            elif op == "read":
                values = instrument.read_registers(step["address"], step["count"], functioncode=3)
            elif op == "write":
                instrument.write_register(step["address"], step["value"], 0, functioncode=6)
                values = []
            elif op == "write_many":
                instrument.write_registers(step["address"], step["values"])
                values = []
            elif op == "echo":
                # minimalmodbus has no call for 08: its generic command, sub-function 0000h.
                sent = b"\x00\x00" + step["value"].to_bytes(2, "big")
                back = instrument._perform_command(8, sent)
                values = [int.from_bytes(back[2:4], "big")] if back[:2] == b"\x00\x00" else []
            elif op == "read_discrete":
                values = instrument.read_bits(step["address"], step["count"], functioncode=2)
            elif op == "read_input":
                values = instrument.read_registers(step["address"], step["count"], functioncode=4)
            elif op == "device_info":
                # minimalmodbus has no call for 2Bh: its generic command, MEI type 0Eh,
                # basic identification (01), object 00.
                instrument._perform_command(0x2B, b"\x0e\x01\x00")
                values = []
            elif op == "read_coils":
                values = instrument.read_bits(step["address"], step["count"], functioncode=1)
            elif op == "write_coil":
                instrument.write_bit(step["address"], int(step["value"]), functioncode=5)
                values = []
            elif op == "write_coils":
                instrument.write_bits(step["address"], [int(v) for v in step["values"]])
                values = []
            else:
                raise ValueError(f"unknown op {op}")
            result = {"ok": True, "values": list(values)}
        except minimalmodbus.SlaveReportedException as error:
            text = str(error).lower()
            code = next((c for name, c in codes.items() if name in text), None)
            if code is None and "error code " in text:
                code = int(text.rsplit("error code ", 1)[1].split()[0])
            result = {"ok": False, "exception": code, "error": str(error)}
        except Exception as error:
            result = {"ok": False, "error": f"{type(error).__name__}: {error}"}
        print(json.dumps(result), flush=True)


def main():
    logging.disable(logging.CRITICAL)
    client, port, station = sys.argv[1], sys.argv[2], int(sys.argv[3])
    mode = sys.argv[4] if len(sys.argv) > 4 else "rtu"
    plan = json.load(sys.stdin)
    if client == "pymodbus":
        run_pymodbus(port, station, plan, mode)
    elif client == "minimalmodbus":
        run_minimalmodbus(port, station, plan, mode)
    else:
        raise SystemExit(f"unknown client {client}")


if __name__ == "__main__":
    main()
