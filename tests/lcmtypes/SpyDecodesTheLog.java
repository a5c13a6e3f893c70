// Decodes every event of an LCM log the way lcm-spy does: the type found by its fingerprint among the
// LCM classes on the class path (lcm.spy.LCMTypeDatabase, lcm-spy's own lookup), built from the
// bytes by the class's (byte[]) constructor. Prints one line per channel: CHANNEL TYPE COUNT, and for
// MAP its grid. Exit 1 when an event's type is unknown or does not decode.
//   java -cp lcm.jar:hunav_lcmtypes_java.jar SpyDecodesTheLog.java run.lcmlog
import java.io.EOFException;
import java.util.TreeMap;

public class SpyDecodesTheLog {
  public static void main(String[] args) throws Exception {
    lcm.spy.LCMTypeDatabase types = new lcm.spy.LCMTypeDatabase();
    lcm.logging.Log log = new lcm.logging.Log(args[0], "r");
    TreeMap<String, Integer> counts = new TreeMap<>();
    TreeMap<String, String> typeOf = new TreeMap<>();
    String grid = null;
    try {
      for (;;) {
        lcm.logging.Log.Event e = log.readNext();
        long fingerprint = new java.io.DataInputStream(new java.io.ByteArrayInputStream(e.data)).readLong();
        Class<?> type = types.getClassByFingerprint(fingerprint);
        if (type == null) {
          System.err.println(e.channel + ": no LCM type has fingerprint " + Long.toHexString(fingerprint));
          System.exit(1);
        }
        Object message = type.getConstructor(byte[].class).newInstance((Object) e.data);
        counts.merge(e.channel, 1, Integer::sum);
        typeOf.put(e.channel, type.getName());
        if (e.channel.equals("MAP")) {
          grid = String.format("MAP %d x %d cells of %s m, episode %d", type.getField("width").get(message),
              type.getField("height").get(message), type.getField("resolution").get(message),
              type.getField("episode").get(message));
        }
      }
    } catch (EOFException end) {
      // the end of the log
    }
    for (String channel : counts.keySet())
      System.out.println(channel + " " + typeOf.get(channel) + " " + counts.get(channel));
    if (grid != null) System.out.println(grid);
  }
}
