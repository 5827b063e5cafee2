// Runs the real lcm-spy (lcm.spy.Spy: its window, type database and
// subscriber) in this JVM under Xvfb, lets it watch the bus, then reads what
// it decoded per channel through reflection and prints one line per channel:
//   channel <TAB> type-or-?? <TAB> received <TAB> undecodable <TAB> seq-of-last-decoded
// so a test can check that lcm-spy, with the edsp jar on its classpath,
// decodes edsp messages (rather than showing "?? <fingerprint>").
//   EDSP_SPY_MAIN=SpyProbe EDSP_SPY_EXTRA_CP=spy_probe.jar deploy/edsp-spy --lcm-url=URL SECONDS [READY_FILE]
import java.lang.reflect.Field;
import java.util.ArrayList;
import java.util.Map;

public class SpyProbe {
  private static Object get(Object o, String name) throws Exception {
    Field f = o.getClass().getDeclaredField(name);
    f.setAccessible(true);
    return f.get(o);
  }

  public static void main(String[] args) throws Exception {
    lcm.spy.Spy spy = new lcm.spy.Spy(args[0].substring("--lcm-url=".length()));
    if (args.length > 2) {  // tell the test the spy is up (the JVM's start-up varies with load)
      new java.io.FileOutputStream(args[2]).close();
    }
    Thread.sleep(Long.parseLong(args[1]) * 1000L);
    Map<?, ?> channels = (Map<?, ?>) get(spy, "channelMap");
    synchronized (get(spy, "channelList")) {
      for (Map.Entry<?, ?> e : new ArrayList<>(channels.entrySet())) {
        Object cd = e.getValue();
        Class<?> cls = (Class<?>) get(cd, "cls");
        Object last = get(cd, "last");
        String seq = "-";
        if (last != null) {
          try {
            seq = String.valueOf(last.getClass().getField("seq").get(last));
          } catch (NoSuchFieldException ex) {
            seq = "no-seq";
          }
        }
        System.out.println(e.getKey() + "\t" + (cls == null ? "??" : cls.getName()) + "\t"
                           + get(cd, "nreceived") + "\t" + get(cd, "nerrors") + "\t" + seq);
      }
    }
    System.out.flush();
    System.exit(0);
  }
}
